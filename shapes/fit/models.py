"""The four primitive models in numpy: minimal-sample hypotheses (PCL's formulas), point
distances, and least-squares refinement.

Parameter layouts (one row per model):

- plane ``[nx, ny, nz, d]`` with ``n . x + d = 0``, n unit;
- sphere ``[cx, cy, cz, r]``;
- cylinder ``[px, py, pz, ax, ay, az, r]``: a point on the axis, the unit axis, the radius;
- cone ``[apx, apy, apz, ax, ay, az, theta]``: apex, unit axis from the apex into the cone,
  half opening angle in radians.

The distances are purely geometric; PITT's normal-distance weights (0.001 and 0.0006) change
them by at most 1.6 mm and are left out. Normals are used where they matter: to build cylinder
and cone hypotheses.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from shapes.arrays import cross3, dot3, norm3, percentiles
from shapes.fit._ransac import levenberg_marquardt
from shapes.types import FloatArray

__all__ = [
    "ConeModel",
    "CylinderModel",
    "PlaneModel",
    "SphereModel",
    "UprightConeModel",
    "UprightCylinderModel",
]

Mask = npt.NDArray[np.bool_]
Index = npt.NDArray[np.intp]

MIN_AXIS_SINE = 0.1
"""A cylinder hypothesis needs two normals whose angle has at least this sine (its axis is
their cross product)."""


def _rows(a: FloatArray, idx: Index) -> FloatArray:
    """``a[idx]`` for the rows of a 2-D array: ``np.take`` gives the same values at a third of
    the cost of an index on an ``(N, 3)`` array."""
    return np.take(a, idx, axis=0)


def _unit(v: FloatArray) -> tuple[FloatArray, FloatArray]:
    norm = norm3(v)
    return v / np.where(norm > 1e-12, norm, 1.0)[..., None], norm


def _axial(
    origin: FloatArray, axis: FloatArray, points: FloatArray
) -> tuple[FloatArray, FloatArray, FloatArray]:
    """For H lines (origin, unit axis) and n points: the axial coordinate ``t``, the distance
    from the line ``rho`` and the squared distance from the origin, each (H, n).

    Written with matrix products instead of (H, n, 3) temporaries; coordinates are taken
    relative to the points' mean to keep the expanded squares accurate.
    """
    pts, org, sq = _centred_squares(origin, points)
    t = axis @ pts.T - dot3(axis, org)[:, None]
    rho = np.sqrt(np.maximum(sq - t * t, 0.0))
    return t, rho, sq


def _centred_squares(
    origin: FloatArray, points: FloatArray
) -> tuple[FloatArray, FloatArray, FloatArray]:
    """The points and H origins taken relative to the points' mean, and the squared distances
    (H, n) between them (expanded as matrix products, :func:`_axial`'s first step)."""
    mean = points.mean(axis=0)
    pts, org = points - mean, origin - mean
    sq = dot3(pts, pts)[None, :] - 2.0 * org @ pts.T + dot3(org, org)[:, None]
    return pts, org, np.maximum(sq, 0.0)


def _refit_rounds(
    params: FloatArray,
    points: FloatArray,
    threshold: float,
    distance: object,
    residual: object,
    rounds: int = 2,
    max_points: int = 250,
) -> FloatArray:
    """Refine on the inliers, re-select inliers, refine again."""
    x = params
    for _ in range(rounds):
        d = distance(x[None, :], points)[0]  # type: ignore[operator]
        inl = points[d < threshold]
        if len(inl) < len(x):
            break
        if len(inl) > max_points:  # an even stride keeps the spread and the determinism
            inl = inl[:: -(-len(inl) // max_points)]
        x = levenberg_marquardt(lambda p, q=inl: residual(p, q), x)  # type: ignore[operator,misc]
    return x


@dataclass(frozen=True)
class PlaneModel:
    """Plane through 3 points; refined by SVD on the inliers."""

    name: str = "plane"
    sample_size: int = 3

    def hypotheses(
        self, points: FloatArray, normals: FloatArray, idx: Index
    ) -> tuple[FloatArray, Mask]:
        a, b, c = _rows(points, idx[:, 0]), _rows(points, idx[:, 1]), _rows(points, idx[:, 2])
        n, norm = _unit(cross3(b - a, c - a))
        d = -np.einsum("ij,ij->i", n, a)
        return np.column_stack((n, d)), norm > 1e-9

    def distances(self, params: FloatArray, points: FloatArray) -> FloatArray:
        return np.asarray(np.abs(params[:, :3] @ points.T + params[:, 3:4]), dtype=np.float64)

    def refine(self, params: FloatArray, points: FloatArray, threshold: float) -> FloatArray:
        inl = points[self.distances(params[None, :], points)[0] < threshold]
        if len(inl) < 3:
            return params
        centre = inl.mean(axis=0)
        n = np.linalg.svd(inl - centre, full_matrices=False)[2][2]
        n = n if n @ params[:3] >= 0 else -n
        return np.concatenate((n, [-n @ centre]))

    def within_limits(self, params: FloatArray) -> bool:
        return bool(np.isfinite(params).all())

    def hopeless(self, normals: FloatArray) -> bool:
        return False  # the normals play no part in its hypotheses


@dataclass(frozen=True)
class SphereModel:
    """Sphere through 4 points (PCL's determinant form, as a 4x4 solve); radius limits apply."""

    min_radius: float = 0.005
    max_radius: float = 0.5
    name: str = "sphere"
    sample_size: int = 4

    def hypotheses(
        self, points: FloatArray, normals: FloatArray, idx: Index
    ) -> tuple[FloatArray, Mask]:
        p = _rows(points, idx)  # (H, 4, 3)
        a = np.concatenate((p, np.ones((*p.shape[:2], 1))), axis=2)
        b = -(p * p).sum(axis=2)
        ok = np.abs(np.linalg.det(a)) > 1e-12
        sol = np.zeros((len(p), 4))
        if ok.any():
            sol[ok] = np.linalg.solve(a[ok], b[ok][..., None])[..., 0]
        centre = -sol[:, :3] / 2
        r2 = (centre * centre).sum(axis=1) - sol[:, 3]
        r = np.sqrt(np.maximum(r2, 0.0))
        ok &= (r2 > 0) & (r >= self.min_radius) & (r <= self.max_radius)
        return np.column_stack((centre, r)), ok

    def distances(self, params: FloatArray, points: FloatArray) -> FloatArray:
        sq = _centred_squares(params[:, :3], points)[2]  # no axis: :func:`_axial`'s squares
        return np.asarray(np.abs(np.sqrt(sq) - params[:, 3:4]), dtype=np.float64)

    @staticmethod
    def residuals(x: FloatArray, pts: FloatArray) -> FloatArray:
        diff = pts[None, :, :] - x[:, None, :3]
        return np.asarray(norm3(diff) - x[:, 3:4], dtype=np.float64)

    def refine(self, params: FloatArray, points: FloatArray, threshold: float) -> FloatArray:
        inl = points[self.distances(params[None, :], points)[0] < threshold]
        x = params
        if len(inl) >= 4:  # algebraic (Kåsa) start, then geometric least squares
            a = np.column_stack((inl, np.ones(len(inl))))
            sol = np.linalg.lstsq(a, -(inl * inl).sum(axis=1), rcond=None)[0]
            c = -sol[:3] / 2
            r2 = c @ c - sol[3]
            if r2 > 0:
                x = np.concatenate((c, [np.sqrt(r2)]))
        return _refit_rounds(x, points, threshold, self.distances, self.residuals)

    def within_limits(self, params: FloatArray) -> bool:
        return bool(np.isfinite(params).all() and self.min_radius <= params[3] <= self.max_radius)

    def hopeless(self, normals: FloatArray) -> bool:
        return False  # the normals play no part in its hypotheses


@dataclass(frozen=True)
class CylinderModel:
    """Cylinder from 2 points with normals: axis = n1 x n2, centre where the normal lines cross.

    With ``with_caps`` (the default) its surface includes the two end discs.
    """

    min_radius: float = 0.005
    max_radius: float = 0.5
    with_caps: bool = True
    cap_band: float = 0.01
    name: str = "cylinder"
    sample_size: int = 2

    def hypotheses(
        self, points: FloatArray, normals: FloatArray, idx: Index
    ) -> tuple[FloatArray, Mask]:
        p1, p2 = _rows(points, idx[:, 0]), _rows(points, idx[:, 1])
        n1, n2 = _rows(normals, idx[:, 0]), _rows(normals, idx[:, 1])
        axis, norm = _unit(cross3(n1, n2))
        ok = norm > MIN_AXIS_SINE

        def flat(v: FloatArray) -> FloatArray:
            return np.asarray(v - np.einsum("ij,ij->i", v, axis)[:, None] * axis, dtype=np.float64)

        q1, q2, m1, m2 = flat(p1), flat(p2), flat(n1), flat(n2)
        # Solve q1 + s m1 = q2 + t m2 in the plane normal to the axis (2 unknowns, 3 equations).
        aa = np.einsum("ij,ij->i", m1, m1)
        bb = np.einsum("ij,ij->i", m1, m2)
        cc = np.einsum("ij,ij->i", m2, m2)
        w = q2 - q1
        dd, ee = np.einsum("ij,ij->i", m1, w), np.einsum("ij,ij->i", m2, w)
        den = aa * cc - bb * bb
        ok &= np.abs(den) > 1e-9
        s = (dd * cc - ee * bb) / np.where(ok, den, 1.0)
        centre = q1 + s[:, None] * m1
        r = (norm3(q1 - centre) + norm3(q2 - centre)) / 2
        ok &= (r >= self.min_radius) & (r <= self.max_radius)
        return np.column_stack((centre, axis, r)), ok

    def lateral_distances(self, params: FloatArray, points: FloatArray) -> FloatArray:
        """Distances to the lateral surface only (PITT's cylinder)."""
        rho = _axial(params[:, :3], params[:, 3:6], points)[1]
        return np.asarray(np.abs(rho - params[:, 6:7]), dtype=np.float64)

    def distances(self, params: FloatArray, points: FloatArray) -> FloatArray:
        """Distances to the lateral surface or, if nearer, one of the two end discs.

        Each disc sits at the mean axial position of the points inside its rim within
        ``cap_band`` of that end of the points (the 1st or 99th percentile). Scoring
        the discs too keeps a flat top from luring RANSAC to a wide cylinder lying on its side.
        """
        if not self.with_caps:
            return self.lateral_distances(params, points)
        t, rho, _ = _axial(params[:, :3], params[:, 3:6], points)
        r = params[:, 6:7]
        # The ends of the points along the axis, ignoring the outer 1 % (stray points), ...
        n = t.shape[1]
        k = max(1, n // 100)
        part = np.partition(t, (k, n - 1 - k), axis=1)
        lo, hi = part[:, k], part[:, n - 1 - k]
        # ... and each disc at the mean of the points inside the rim near that end (noise
        # spreads a disc along the axis, so the extreme would sit too far out).
        inside = rho < 0.9 * r
        ends = []
        for end, near in (
            (lo, np.abs(t - lo[:, None]) < self.cap_band),
            (hi, np.abs(t - hi[:, None]) < self.cap_band),
        ):
            m = inside & near
            count = m.sum(axis=1)
            mean = (t * m).sum(axis=1) / np.maximum(count, 1)
            ends.append(np.where(count > 0, mean, end)[:, None])
        excess = np.maximum(rho - r, 0.0)
        # The nearer disc is the one nearer along the axis (hypot grows with either side).
        cap = np.hypot(np.minimum(np.abs(t - ends[0]), np.abs(t - ends[1])), excess)
        return np.asarray(np.minimum(np.abs(rho - r), cap), dtype=np.float64)

    @staticmethod
    def residuals(x: FloatArray, pts: FloatArray) -> FloatArray:
        axis = _unit(x[:, 3:6])[0][:, None, :]
        v = pts[None, :, :] - x[:, None, :3]
        radial = v - dot3(v, axis)[..., None] * axis
        return np.asarray(norm3(radial) - x[:, 6:7], dtype=np.float64)

    def refine(self, params: FloatArray, points: FloatArray, threshold: float) -> FloatArray:
        # Points of a flat end disc that lie within the threshold of the rim would pull the
        # radius in: refine on the lateral band away from both ends.
        v = points - params[:3]
        t = v @ params[3:6]
        inl = self.lateral_distances(params[None, :], points)[0] < threshold
        if inl.sum() >= 10:
            lo, hi = percentiles(t[inl], [2.0, 98.0])
            band = (t > lo + 1.5 * threshold) & (t < hi - 1.5 * threshold)
            if (band & inl).sum() >= 10:
                points = points[band]
        x = _refit_rounds(params, points, threshold, self.lateral_distances, self.residuals)
        axis = x[3:6] / np.linalg.norm(x[3:6])
        return np.concatenate((x[:3], axis, [abs(x[6])]))

    def within_limits(self, params: FloatArray) -> bool:
        return bool(np.isfinite(params).all() and self.min_radius <= params[6] <= self.max_radius)

    def hopeless(self, normals: FloatArray) -> bool:
        """Whether every pair of normals is too near parallel for an axis (the sine of their
        angle at most ``MIN_AXIS_SINE``, which :meth:`hypotheses` rejects): true when they all
        lie within ``alpha`` of one line with ``sin(2 alpha)`` below that bound, as on a
        cluster of fewer points than a normal's neighbours (all normals are one)."""
        if len(normals) < 2:
            return True
        if not np.isfinite(normals).all():
            return False  # no shortcut: the full search decides, as before
        line = np.linalg.eigh(normals.T @ normals)[1][:, 2]
        sine = float(np.linalg.norm(np.cross(normals, line), axis=1).max())
        # Two normals within alpha of the line are within 2 alpha of each other (mod pi).
        return sine < math.sin(math.asin(0.99 * MIN_AXIS_SINE) / 2)


@dataclass(frozen=True)
class ConeModel:
    """Cone from ``sample_size`` (>= 3) points with normals: the apex where their tangent planes
    meet (least squares), the axis normal to the unit vectors from the apex to the points."""

    min_half_angle: float = np.radians(10.0)
    max_half_angle: float = np.radians(80.0)
    max_apex_distance: float = 1.0
    with_base: bool = True
    cap_band: float = 0.01
    name: str = "cone"
    sample_size: int = 3
    """Points per hypothesis: 3 is the minimum; more average out the noise of the normals."""

    def hypotheses(
        self, points: FloatArray, normals: FloatArray, idx: Index
    ) -> tuple[FloatArray, Mask]:
        p, n = _rows(points, idx), _rows(normals, idx)  # (H, s, 3)
        # The apex lies on every tangent plane n . x = n . p: least squares over the sample
        # (PCL's three-plane intersection when s = 3).
        dots = np.einsum("hsi,hsi->hs", p, n)
        ntn = np.einsum("hsi,hsj->hij", n, n)
        ntd = np.einsum("hsi,hs->hi", n, dots)
        ok = np.abs(np.linalg.det(ntn)) > 1e-9
        apex = np.zeros((len(p), 3))
        if ok.any():
            apex[ok] = np.linalg.solve(ntn[ok], ntd[ok][..., None])[..., 0]
        # The unit vectors from the apex to the points make one angle with the axis: they lie
        # on a plane whose normal is the axis.
        u = _unit(p - apex[:, None, :])[0]
        if u.shape[1] == 3:  # three unit vectors: their plane's normal, a cross product
            axis = _unit(cross3(u[:, 1] - u[:, 0], u[:, 2] - u[:, 0]))[0]
        else:
            centred = u - u.mean(axis=1, keepdims=True)
            axis = np.linalg.eigh(np.einsum("hsi,hsj->hij", centred, centred))[1][:, :, 0]
        cosines = np.einsum("hsi,hi->hs", u, axis)
        axis[cosines.mean(axis=1) < 0] *= -1
        theta = np.arccos(np.clip(np.abs(cosines), -1, 1)).mean(axis=1)
        ok &= np.isfinite(axis).all(axis=1)
        ok &= (theta >= self.min_half_angle) & (theta <= self.max_half_angle)
        ok &= norm3(apex - p[:, 0]) <= self.max_apex_distance
        return np.column_stack((apex, axis, theta)), ok

    def lateral_distances(self, params: FloatArray, points: FloatArray) -> FloatArray:
        """Distances to the lateral surface only (PITT's cone)."""
        return self._lateral(params, *_axial(params[:, :3], params[:, 3:6], points))

    @staticmethod
    def _lateral(params: FloatArray, k: FloatArray, rho: FloatArray, sq: FloatArray) -> FloatArray:
        c, s = np.cos(params[:, 6:7]), np.sin(params[:, 6:7])
        along = k * c + rho * s
        d = np.where(along >= 0, np.abs(rho * c - k * s), np.sqrt(sq))
        return np.asarray(d, dtype=np.float64)

    def distances(self, params: FloatArray, points: FloatArray) -> FloatArray:
        """Distances to the lateral surface or, if nearer, the base disc.

        The base sits at the mean axial position of the points inside its rim within
        ``cap_band`` of the far end of the points (their 99th percentile along the axis).
        A cone lying on its side shows its flat base to the camera; without the disc, that
        face hands the cluster to "plane".
        """
        k, rho, sq = _axial(params[:, :3], params[:, 3:6], points)
        lateral = self._lateral(params, k, rho, sq)
        if not self.with_base:
            return lateral
        n = k.shape[1]
        top = max(1, n // 100)
        end = np.partition(k, n - 1 - top, axis=1)[:, n - 1 - top][:, None]
        rim = np.maximum(end, 0.0) * np.tan(params[:, 6:7])
        near = (np.abs(k - end) < self.cap_band) & (rho < 0.9 * rim)
        count = near.sum(axis=1)
        base = np.where(
            count[:, None] > 0, (k * near).sum(axis=1)[:, None] / np.maximum(count[:, None], 1), end
        )
        radius = np.maximum(base, 0.0) * np.tan(params[:, 6:7])
        disc = np.hypot(k - base, np.maximum(rho - radius, 0.0))
        return np.asarray(np.minimum(lateral, disc), dtype=np.float64)

    @staticmethod
    def residuals(x: FloatArray, pts: FloatArray) -> FloatArray:
        axis = _unit(x[:, 3:6])[0][:, None, :]
        v = pts[None, :, :] - x[:, None, :3]
        k = dot3(v, axis)
        rho = norm3(v - k[..., None] * axis)
        return np.asarray(rho * np.cos(x[:, 6:7]) - k * np.sin(x[:, 6:7]), dtype=np.float64)

    def refine(self, params: FloatArray, points: FloatArray, threshold: float) -> FloatArray:
        # The base disc's points would pull the lateral surface: refine on the lateral inliers.
        x = _refit_rounds(params, points, threshold, self.lateral_distances, self.residuals)
        axis = x[3:6] / np.linalg.norm(x[3:6])
        return np.concatenate((x[:3], axis, [x[6]]))

    def within_limits(self, params: FloatArray) -> bool:
        return bool(
            np.isfinite(params).all() and self.min_half_angle <= params[6] <= self.max_half_angle
        )

    def hopeless(self, normals: FloatArray) -> bool:
        return False  # not worked out for three or more normals


@dataclass(frozen=True)
class UprightConeModel:
    """A cone standing on a support, apex up: its axis is the support normal ``up``, so two
    points with normals fix it. The horizontal parts of their normals point away from the axis
    (which crosses both lines, as for a cylinder), the vertical part is the sine of the half
    angle, and each point's distance from the axis gives the apex height. Distances, limits and
    refinement are the free cone's (:class:`ConeModel`), so the refinement may tilt the axis.
    """

    cone: ConeModel
    up: tuple[float, float, float] = (0.0, 0.0, 1.0)
    name: str = "upright cone"
    sample_size: int = 2

    def hypotheses(
        self, points: FloatArray, normals: FloatArray, idx: Index
    ) -> tuple[FloatArray, Mask]:
        up = np.asarray(self.up, dtype=np.float64)
        p, n = _rows(points, idx), _rows(normals, idx)  # (H, 2, 3)
        n = n * np.where((n @ up) < 0, -1.0, 1.0)[..., None]  # the normals of a cone point up
        sin_theta = (n @ up).mean(axis=1)
        flat_p = p - (p @ up)[..., None] * up
        flat_n = n - (n @ up)[..., None] * up
        centre, ok = _lines_crossing(flat_p, flat_n)
        theta = np.arcsin(np.clip(sin_theta, 0.0, 1.0))
        rho = norm3(flat_p - centre[:, None, :])
        tan = np.tan(np.maximum(theta, 1e-6))
        top = ((p @ up) + rho / tan[:, None]).mean(axis=1)
        apex = centre + top[:, None] * up
        ok &= (theta >= self.cone.min_half_angle) & (theta <= self.cone.max_half_angle)
        ok &= np.isfinite(apex).all(axis=1)
        axis = np.broadcast_to(-up, apex.shape)
        return np.column_stack((apex, axis, theta)), ok

    def distances(self, params: FloatArray, points: FloatArray) -> FloatArray:
        return self.cone.distances(params, points)

    def refine(self, params: FloatArray, points: FloatArray, threshold: float) -> FloatArray:
        return self.cone.refine(params, points, threshold)

    def within_limits(self, params: FloatArray) -> bool:
        return self.cone.within_limits(params)

    def hopeless(self, normals: FloatArray) -> bool:
        return False  # not worked out for the flattened normals


@dataclass(frozen=True)
class UprightCylinderModel:
    """A cylinder standing on a support: its axis is the support normal ``up`` (gravity's
    direction, the commonest axis of a thing on a table), so two points with normals fix it:
    seen along ``up``, both normals point away from the axis, which lies where their lines
    cross; the radius is the mean distance of the two points from it. Distances, limits and
    refinement are the free cylinder's (:class:`CylinderModel`), so the refinement may tilt
    the axis.
    """

    cylinder: CylinderModel
    up: tuple[float, float, float] = (0.0, 0.0, 1.0)
    name: str = "upright cylinder"
    sample_size: int = 2

    def hypotheses(
        self, points: FloatArray, normals: FloatArray, idx: Index
    ) -> tuple[FloatArray, Mask]:
        up = np.asarray(self.up, dtype=np.float64)
        p, n = _rows(points, idx), _rows(normals, idx)  # (H, 2, 3)
        flat_p = p - (p @ up)[..., None] * up
        flat_n = n - (n @ up)[..., None] * up
        centre, ok = _lines_crossing(flat_p, flat_n)
        r = norm3(flat_p - centre[:, None, :]).mean(axis=1)
        ok &= (r >= self.cylinder.min_radius) & (r <= self.cylinder.max_radius)
        ok &= np.isfinite(centre).all(axis=1)
        axis = np.broadcast_to(up, centre.shape)
        return np.column_stack((centre, axis, r)), ok

    def distances(self, params: FloatArray, points: FloatArray) -> FloatArray:
        return self.cylinder.distances(params, points)

    def refine(self, params: FloatArray, points: FloatArray, threshold: float) -> FloatArray:
        return self.cylinder.refine(params, points, threshold)

    def within_limits(self, params: FloatArray) -> bool:
        return self.cylinder.within_limits(params)

    def hopeless(self, normals: FloatArray) -> bool:
        return False  # not worked out for the flattened normals


def _lines_crossing(flat_p: FloatArray, flat_n: FloatArray) -> tuple[FloatArray, Mask]:
    """Where the lines through two points along their normals cross, for each hypothesis
    (``(H, 2, 3)`` points and normals, both flattened onto the plane across a standing axis):
    the point of the first line nearest the second (least squares), and whether the lines are
    not parallel."""
    m1, m2, q1, q2 = flat_n[:, 0], flat_n[:, 1], flat_p[:, 0], flat_p[:, 1]
    aa, bb, cc = (m1 * m1).sum(1), (m1 * m2).sum(1), (m2 * m2).sum(1)
    w = q2 - q1
    dd, ee = (m1 * w).sum(1), (m2 * w).sum(1)
    den = aa * cc - bb * bb
    ok = np.abs(den) > 1e-9
    s = (dd * cc - ee * bb) / np.where(ok, den, 1.0)
    return q1 + s[:, None] * m1, ok
