"""The side of a round thing standing on its support, as a profile: its radius against height.

The axis is the support's normal through the centre of the circle fitted to the side's points
(algebraic least squares, seen along the normal); the radius is then fitted as a straight line
of the height. :func:`side_profile` gives that line; ``shapes.fit.select`` reads from it whether
a standing thing narrows upwards (a cone) and, for a thing that widens upwards (a paper cup, a
flower pot), a standing cylinder scored with the taper taken out
(:func:`cylinder_without_taper`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from shapes.arrays import percentiles
from shapes.fit.models import CylinderModel
from shapes.types import FloatArray, SupportPlane

__all__ = ["SideProfile", "cylinder_without_taper", "side_profile"]


@dataclass(frozen=True)
class SideProfile:
    """A standing thing's side: the foot of its axis on the support, its radius as a straight
    line of the height over the support, the robust spread of the side's radii about that line
    and the side's 5th and 95th percentile heights (all in metres)."""

    foot: FloatArray
    radius_at_support_m: float
    slope: float
    """Radius gained per metre of height (negative when the side narrows upwards)."""
    spread_m: float
    low_m: float
    high_m: float

    @property
    def drop_m(self) -> float:
        """The radius lost from the bottom to the top of the side (positive: narrows upwards)."""
        return -self.slope * (self.high_m - self.low_m)

    def radius_at(self, height_m: FloatArray | float) -> FloatArray:
        """The profile's radius at heights over the support."""
        return np.asarray(self.radius_at_support_m + self.slope * np.asarray(height_m))


def side_profile(points: FloatArray, support: SupportPlane, cut_m: float) -> SideProfile | None:
    """The profile of the side of a thing standing on ``support``: its points lower than
    ``cut_m`` under the thing's top (the 99th percentile of the heights; the top, a cylinder's
    flat end, is left out). None with fewer than 20 side points.

    >>> angle = np.linspace(-1.2, 1.2, 40)
    >>> h = np.repeat(np.linspace(0.0, 0.1, 20), 40)
    >>> r = 0.03 + 0.07 * h  # a cup widening by 7 mm over 10 cm
    >>> a = np.tile(angle, 20)
    >>> cup = np.column_stack((0.2 + r * np.sin(a), -r * np.cos(a), h))
    >>> found = side_profile(cup, SupportPlane((0.0, 0.0, 1.0), 0.0), 0.01)
    >>> bool(np.linalg.norm(found.foot - (0.2, 0.0, 0.0)) < 0.003), round(found.slope, 3)
    (True, 0.07)
    >>> round(found.drop_m, 4)  # widens by 6.3 mm between the side's 5th and 95th percentile
    -0.0063
    """
    normal = np.asarray(support.normal, dtype=np.float64)
    height = points @ normal + support.offset
    side = height < percentiles(height, [99])[0] - cut_m
    if side.sum() < 20:
        return None
    e1 = np.cross(normal, [1.0, 0.0, 0.0] if abs(normal[0]) < 0.9 else [0.0, 1.0, 0.0])
    e1 /= np.linalg.norm(e1)
    e2 = np.cross(normal, e1)
    a, b, h = points[side] @ e1, points[side] @ e2, height[side]
    design = np.column_stack((a, b, np.ones_like(a)))
    sol = np.linalg.lstsq(design, a**2 + b**2, rcond=None)[0]
    rho = np.hypot(a - sol[0] / 2, b - sol[1] / 2)
    line = np.column_stack((np.ones_like(h), h))
    coef = np.linalg.lstsq(line, rho, rcond=None)[0]
    residual = rho - line @ coef
    spread = 1.4826 * float(np.median(np.abs(residual - np.median(residual))))
    lo, hi = percentiles(h, [5, 95])
    foot = sol[0] / 2 * e1 + sol[1] / 2 * e2 - support.offset * normal
    return SideProfile(foot, float(coef[0]), float(coef[1]), spread, float(lo), float(hi))


def cylinder_without_taper(
    points: FloatArray,
    profile: SideProfile,
    support: SupportPlane,
    model: CylinderModel,
) -> tuple[FloatArray, FloatArray]:
    """The standing cylinder of the profile's radius at mid-side (parameters: a point on the
    axis, the support's normal, the radius) and the distances of ``points`` to it once the
    taper is taken out: each point is moved along its radius by the profile's excess at its
    height over the mid-side radius, then measured to the cylinder with its end discs
    (``model``).

    >>> table = SupportPlane((0.0, 0.0, 1.0), 0.0)
    >>> a, h = np.meshgrid(np.linspace(-1.2, 1.2, 30), np.linspace(0.0, 0.1, 20))
    >>> r = 0.03 + 0.07 * h.ravel()
    >>> cup = np.column_stack((r * np.sin(a.ravel()), -r * np.cos(a.ravel()), h.ravel()))
    >>> found = side_profile(cup, table, 0.01)
    >>> params, d = cylinder_without_taper(cup, found, table, CylinderModel())
    >>> round(float(params[6]), 4), bool(d.max() < 1e-3)
    (0.0317, True)
    """
    normal = np.asarray(support.normal, dtype=np.float64)
    mid = float(profile.radius_at((profile.low_m + profile.high_m) / 2))
    params = np.concatenate((profile.foot, normal, [mid]))
    rel = points - profile.foot
    height = rel @ normal
    radial = rel - np.outer(height, normal)
    rho = np.linalg.norm(radial, axis=1)
    excess = profile.radius_at(height) - mid
    moved = np.maximum(rho - excess, 0.0)
    scale = np.divide(moved, rho, out=np.ones_like(rho), where=rho > 0)
    untapered = profile.foot + np.outer(height, normal) + radial * scale[:, None]
    return params, model.distances(params[None, :], untapered)[0]
