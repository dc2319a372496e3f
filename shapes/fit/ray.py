"""Errors along the sensor's rays.

A depth sensor measures a range along each pixel's ray; its noise moves a point along that ray,
not along the surface's normal. The error of a point under a candidate surface is therefore how
far the point must move along its ray, the line from the sensor's centre through it, to reach the
surface the sensor would see: its range minus the range at which the ray first meets the
surface (:func:`ray_errors`). A ray that meets the surface nowhere has no such error: the
surface does not cover the pixel at all (under range noise the pixel's direction is exact).

Each model's surface is the one its distances describe (:mod:`shapes.fit.models`), closed where
the points end: a sphere; a cylinder's side between its two end discs, at the 1st and 99th
percentiles of the points along the axis; a cone's side (the nappe the axis points into) from
the apex to its base disc, at the 99th percentile; a plane. The discs of a cylinder or cone are
then moved in to where they cost least along the rays (:func:`fit_ends`): range noise spreads a
flat top along the axis, so the outermost points lie beyond it. :func:`refine_on_rays` fits a
model's parameters under the same error, :func:`sphere_from_outline` gives a sphere to start
from.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from shapes.fit._ransac import levenberg_marquardt
from shapes.fit.models import ConeModel, CylinderModel, PlaneModel, SphereModel
from shapes.types import FloatArray

__all__ = [
    "RayModel",
    "fit_ends",
    "ray_cost",
    "ray_directions",
    "ray_errors",
    "refine_on_rays",
    "sphere_from_outline",
    "truncated_cost",
]

Mask = npt.NDArray[np.bool_]

RayModel = SphereModel | CylinderModel | ConeModel | PlaneModel
"""The models whose surfaces a ray can be cast against."""


def ray_directions(points: FloatArray, viewpoint: FloatArray) -> FloatArray:
    """Unit vectors from ``viewpoint`` (the sensor's centre, in the points' frame) to each point.

    Raises ValueError if a point lies at the viewpoint.

    >>> ray_directions(np.array([[0.0, 0.0, 2.0]]), np.zeros(3)).tolist()
    [[0.0, 0.0, 1.0]]
    """
    rays = np.asarray(points, dtype=np.float64) - np.asarray(viewpoint, dtype=np.float64)
    length = np.linalg.norm(rays, axis=1)
    if np.any(length <= 0):
        raise ValueError("viewpoint: expected the sensor's centre away from every point")
    return np.asarray(rays / length[:, None], dtype=np.float64)


def _first(ranges: FloatArray, *meetings: tuple[FloatArray, Mask]) -> FloatArray:
    """``|range - s|`` for the first meeting ``s`` (the nearest the sensor, in front of it)
    among the valid ones, else inf: the surface the sensor sees along a ray is the first it
    meets, so a point is never explained by a surface hidden behind another part of the same
    candidate."""
    first = np.full(np.broadcast(ranges, meetings[0][0]).shape, np.inf)
    for s, valid in meetings:
        first = np.where(valid & (s > 0), np.minimum(first, s), first)
    return np.asarray(np.abs(ranges - first), dtype=np.float64)


def _roots(a: FloatArray, b: FloatArray, c: FloatArray) -> tuple[FloatArray, FloatArray, Mask]:
    """Both real roots of ``a s² + 2 b s + c = 0`` and where they exist (``a`` may be 0)."""
    disc = b * b - a * c
    real = disc >= 0
    root = np.sqrt(np.maximum(disc, 0.0))
    flat = np.abs(a) < 1e-12
    safe = np.where(flat, 1.0, a)
    lo = np.where(flat, -c / np.where(np.abs(b) > 1e-15, 2 * b, 1e-15), (-b - root) / safe)
    hi = np.where(flat, lo, (-b + root) / safe)
    return lo, hi, real | flat


def _disc(
    at: FloatArray,
    radius: FloatArray,
    wa: FloatArray,
    ua: FloatArray,
    wu: FloatArray,
    ww: FloatArray,
) -> tuple[FloatArray, Mask]:
    """Where each ray meets the disc at axial position ``at`` of ``radius``: ``(s, valid)``,
    each ``(m, n)``. The ray is ``w + s u`` from the axis's origin (``w`` the sensor's centre
    from it); ``wa``, ``ua``: ``w`` and ``u`` along the axis, ``wu``, ``ww``: their dot
    products."""
    crosses = np.abs(ua) > 1e-12
    s = (at - wa) / np.where(crosses, ua, 1e-12)
    # |w + s u|² minus the square of its axial part (which is ``at``): the squared distance
    # from the axis where the ray crosses the disc's plane.
    rho2 = ww + 2 * s * wu + s * s - at * at
    return s, crosses & (rho2 <= radius * radius)


def _percentile_ends(
    origin: FloatArray, axis: FloatArray, points: FloatArray
) -> tuple[FloatArray, FloatArray]:
    """The 1st and 99th percentiles of the points' axial positions, ``(m, 1)`` each."""
    t = axis @ points.T - (axis * origin).sum(axis=1)[:, None]
    n = t.shape[1]
    k = max(1, n // 100) if n > 2 else 0
    part = np.partition(t, (k, n - 1 - k), axis=1)
    return part[:, k : k + 1], part[:, n - 1 - k : n - k]


def ray_errors(
    model: RayModel,
    params: FloatArray,
    points: FloatArray,
    viewpoint: FloatArray,
    *,
    ends: tuple[FloatArray, FloatArray] | None = None,
) -> FloatArray:
    """``(m, n)``: for each of ``m`` parameter rows of ``model``, each point's error along its
    ray from ``viewpoint`` (module docstring), ``inf`` where the ray misses the surface.

    ``ends``: for a cylinder, the axial positions ``(m, 1)`` of its two end discs; for a cone,
    the second is its base's (the first is not used); by default the 1st and 99th percentiles
    of the points along the axis (:func:`fit_ends` finds better ones).

    >>> pts = np.array([[0.0, 0.0, 0.96], [0.0, 0.2, 1.0]])
    >>> ray_errors(SphereModel(), np.array([[0.0, 0.0, 1.0, 0.05]]), pts, np.zeros(3)).round(6)
    array([[0.01,  inf]])
    """
    return _errors(model, params, points, _Rays.of(points, viewpoint), ends)


@dataclass(frozen=True)
class _Rays:
    """The sensor's centre ``eye``, each point's range ``(1, n)`` and unit ray ``(n, 3)``:
    what :func:`ray_errors` needs of the points whatever the parameters (a refinement computes
    them once for all its steps)."""

    eye: FloatArray
    ranges: FloatArray
    rays: FloatArray

    @staticmethod
    def of(points: FloatArray, viewpoint: FloatArray) -> _Rays:
        eye = np.asarray(viewpoint, dtype=np.float64)
        offsets = np.asarray(points, dtype=np.float64) - eye
        ranges = np.linalg.norm(offsets, axis=1)[None, :]
        return _Rays(eye, ranges, offsets / ranges.T)


def _errors(
    model: RayModel,
    params: FloatArray,
    points: FloatArray,
    along: _Rays,
    ends: tuple[FloatArray, FloatArray] | None,
) -> FloatArray:
    """:func:`ray_errors` with the points' rays given."""
    eye, ranges, rays = along.eye, along.ranges, along.rays
    x = np.atleast_2d(np.asarray(params, dtype=np.float64))
    if isinstance(model, PlaneModel):
        n, d = x[:, :3], x[:, 3:4]
        across = n @ rays.T
        safe = np.where(np.abs(across) > 1e-12, across, 1e-12)
        s = -((n @ eye)[:, None] + d) / safe
        return _first(ranges, (s, np.abs(across) > 1e-12))
    if isinstance(model, SphereModel):
        w = eye - x[:, :3]
        b = w @ rays.T
        c = (w * w).sum(axis=1)[:, None] - x[:, 3:4] ** 2
        lo, hi, real = _roots(np.ones_like(b), b, c)
        return _first(ranges, (lo, real), (hi, real))
    origin = x[:, :3]
    axis = x[:, 3:6] / np.linalg.norm(x[:, 3:6], axis=1, keepdims=True)
    lo_end, hi_end = ends if ends is not None else _percentile_ends(origin, axis, points)
    w = eye - origin
    wa = (w * axis).sum(axis=1)[:, None]  # (m, 1)
    ua = axis @ rays.T  # (m, n)
    wu = w @ rays.T
    ww = (w * w).sum(axis=1)[:, None]
    if isinstance(model, CylinderModel):
        r = x[:, 6:7]
        # The side between the ends: |(w + s u) - ((w + s u).a) a|² = r², lo <= (w + s u).a <= hi
        lo, hi, real = _roots(1.0 - ua * ua, wu - wa * ua, ww - wa * wa - r * r)
        meetings = [(s, real & (wa + s * ua >= lo_end) & (wa + s * ua <= hi_end)) for s in (lo, hi)]
        if model.with_caps:
            meetings += [_disc(end, r, wa, ua, wu, ww) for end in (lo_end, hi_end)]
        return _first(ranges, *meetings)
    c2 = np.cos(x[:, 6:7]) ** 2
    tan = np.tan(x[:, 6:7])
    base = np.maximum(hi_end, 0.0)
    # The side from the apex to the base (the nappe the axis points into):
    # ((w + s u).a)² = cos² |w + s u|², 0 <= (w + s u).a <= base
    lo, hi, real = _roots(ua * ua - c2, wa * ua - c2 * wu, wa * wa - c2 * ww)
    meetings = [(s, real & (wa + s * ua >= 0) & (wa + s * ua <= base)) for s in (lo, hi)]
    if model.with_base:
        meetings.append(_disc(base, base * tan, wa, ua, wu, ww))
    return _first(ranges, *meetings)


def truncated_cost(errors: FloatArray, threshold: float) -> FloatArray:
    """The MSAC cost ``mean(min(e / threshold, 1)²)`` of each row of errors (inf counts 1)."""
    return np.asarray(np.mean(np.minimum(errors / threshold, 1.0) ** 2, axis=-1))


def fit_ends(
    model: CylinderModel | ConeModel,
    params: FloatArray,
    points: FloatArray,
    viewpoint: FloatArray,
    *,
    threshold: float,
    steps: int = 12,
) -> tuple[FloatArray, FloatArray]:
    """The end discs' axial positions ``(1, 1)`` of one cylinder or cone that cost least along
    the rays: each end is moved in from the points' 1st or 99th percentile along the axis in
    ``steps`` steps of a quarter of ``threshold`` (range noise spreads a flat top along the
    axis, so the outermost points lie beyond it), the far end first. A cone has one disc, its
    base."""
    x = np.asarray(params, dtype=np.float64)[None, :]
    axis = x[:, 3:6] / np.linalg.norm(x[:, 3:6])
    lo, hi = _percentile_ends(x[:, :3], axis, points)
    shifts = (np.arange(steps + 1) * threshold / 4)[:, None]
    rows = np.repeat(x, steps + 1, axis=0)
    ones = np.ones_like(shifts)
    along = _Rays.of(points, viewpoint)
    cost = truncated_cost(_errors(model, rows, points, along, (lo * ones, hi - shifts)), threshold)
    hi = hi - shifts[int(np.argmin(cost))]
    if isinstance(model, CylinderModel):
        cost = truncated_cost(
            _errors(model, rows, points, along, (lo + shifts, hi * ones)), threshold
        )
        lo = lo + shifts[int(np.argmin(cost))]
    return lo, hi


def refine_on_rays(
    model: RayModel,
    params: FloatArray,
    points: FloatArray,
    viewpoint: FloatArray,
    *,
    threshold: float,
    iterations: int = 8,
    ends: tuple[FloatArray, FloatArray] | None = None,
) -> FloatArray:
    """Parameters refined from ``params`` to minimise the squared errors along the rays
    (Levenberg-Marquardt; a cylinder's or cone's end discs held still: ``ends``, else
    :func:`fit_ends` of ``params``). An error ``e`` counts as ``threshold * tanh(e /
    threshold)`` (an outlier pulls no further than ``threshold``, yet still a little), and a ray
    that misses the surface counts ``threshold`` plus the point's distance to the surface, so
    that the surface moves to cover every ray.

    >>> rng = np.random.default_rng(0)
    >>> d = rng.normal(size=(300, 3))
    >>> d[:, 2] = -np.abs(d[:, 2])
    >>> on = 0.05 * d / np.linalg.norm(d, axis=1)[:, None] + [0.0, 0.0, 1.0]
    >>> x = refine_on_rays(SphereModel(), np.array([0.002, 0.0, 1.002, 0.049]), on, np.zeros(3),
    ...                    threshold=0.01, iterations=20)
    >>> bool(np.abs(x - [0.0, 0.0, 1.0, 0.05]).max() < 1e-3)
    True
    """
    if ends is None and isinstance(model, (CylinderModel, ConeModel)):
        ends = fit_ends(model, params, points, viewpoint, threshold=threshold)
    along = _Rays.of(points, viewpoint)

    def residuals(x: FloatArray) -> FloatArray:
        e = _errors(model, x, points, along, ends)
        missed = ~np.isfinite(e)
        if missed.any():
            e = np.where(missed, threshold + model.distances(x, points), e)
        return np.asarray(np.where(missed, e, threshold * np.tanh(e / threshold)), dtype=np.float64)

    x = levenberg_marquardt(residuals, np.asarray(params, dtype=np.float64), iterations=iterations)
    if len(x) == 7:  # a cylinder's or cone's axis: unit again
        x = np.concatenate((x[:3], x[3:6] / np.linalg.norm(x[3:6]), x[6:]))
    return x


def ray_cost(
    model: RayModel,
    params: FloatArray,
    points: FloatArray,
    viewpoint: FloatArray,
    *,
    threshold: float,
    ends: tuple[FloatArray, FloatArray] | None = None,
) -> float:
    """The truncated cost of one candidate along the rays (a cylinder's or cone's end discs:
    ``ends``, else :func:`fit_ends` of ``params``)."""
    if ends is None and isinstance(model, (CylinderModel, ConeModel)):
        ends = fit_ends(model, params, points, viewpoint, threshold=threshold)
    errors = ray_errors(model, params, points, viewpoint, ends=ends)
    return float(truncated_cost(errors, threshold)[0])


def sphere_from_outline(points: FloatArray, viewpoint: FloatArray) -> FloatArray:
    """A first guess ``[cx, cy, cz, r]`` of the sphere the points would be the visible part of,
    from their outline alone (the ranges, noisy, play no part but in their mean): the radius is
    half the points' spread across the mean ray (the 2nd to 98th percentiles, along the wider of
    the two directions across it), the centre lies behind the points' mean by two thirds of the
    radius along the mean ray (the mean depth of a half sphere seen from far, over its disc).

    >>> rng = np.random.default_rng(0)
    >>> d = rng.normal(size=(2000, 3))
    >>> d[:, 2] = -np.abs(d[:, 2])
    >>> on = 0.05 * d / np.linalg.norm(d, axis=1)[:, None] + [0.0, 0.0, 2.0]
    >>> guess = sphere_from_outline(on, np.zeros(3))
    >>> bool(np.abs(guess - [0.0, 0.0, 2.0, 0.05]).max() < 0.01)
    True
    """
    pts = np.asarray(points, dtype=np.float64)
    mean = pts.mean(axis=0)
    view = mean - np.asarray(viewpoint, dtype=np.float64)
    view /= np.linalg.norm(view)
    helper = np.array([1.0, 0.0, 0.0]) if abs(view[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    e1 = np.cross(view, helper)
    e1 /= np.linalg.norm(e1)
    e2 = np.cross(view, e1)
    spans = [float(np.subtract(*np.percentile(pts @ e, [98, 2]))) for e in (e1, e2)]
    radius = max(spans) / 2 / 0.96  # the 2nd-98th percentiles of a disc's width span 0.96 of it
    return np.concatenate((mean + 2.0 / 3.0 * radius * view, [radius]))
