"""What a model's free parameters cost it when the fit's models meet (``shapes.fit.select``,
"Faces charged for their parameters").

The fit scores a candidate by ``mean(min(d / T, 1)²)``. Where the threshold ``T`` is set by the
depth noise it is ``noise_factor`` noise deviations, so a point's cost is its squared error in
noise variances over ``noise_factor²``, and the Bayesian information criterion (the squared
errors in variances plus ``k ln n`` for ``k`` free parameters and ``n`` points), divided by
``noise_factor² n``, is the cost plus ``k ln n / (noise_factor² n)``.
"""

from __future__ import annotations

import math

from shapes.types import ShapeKind

__all__ = ["FREE_PARAMETERS", "PLANE_PARAMETERS", "parameter_charges"]

FREE_PARAMETERS = {
    ShapeKind.SPHERE: 4,  # centre, radius
    ShapeKind.CYLINDER: 5,  # axis (a point across it and a direction), radius
    ShapeKind.CONE: 6,  # apex, axis direction, half angle
}
"""The curved models' free parameters (the end discs of a cylinder or cone come from its points,
not from the fit)."""
PLANE_PARAMETERS = 3
"""A plane's free parameters (a direction and an offset); a union of faces has as many a face."""


def parameter_charges(
    faces: int, points: int, *, charge: float, noise_factor: float
) -> dict[ShapeKind, float]:
    """What each kind's cost pays for its free parameters, the planes being a union of ``faces``
    faces, on ``points`` points scored: ``charge`` times the information criterion's charge
    (module docstring); ``noise_factor``: the thresholds in noise deviations.

    Raises ValueError when ``points`` is under 2 or ``noise_factor`` is not positive.

    >>> charges = parameter_charges(3, 300, charge=1.0, noise_factor=3.0)
    >>> round(charges[ShapeKind.PLANE] - charges[ShapeKind.CYLINDER], 4)
    0.0085
    """
    if points < 2 or not noise_factor > 0:
        raise ValueError(
            f"points, noise_factor: expected at least 2 and a positive factor, got {points}, "
            f"{noise_factor}"
        )
    unit = charge * math.log(points) / (noise_factor**2 * points)
    charges = {kind: unit * k for kind, k in FREE_PARAMETERS.items()}
    charges[ShapeKind.PLANE] = unit * PLANE_PARAMETERS * faces
    return charges
