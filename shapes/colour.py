"""Colour of an object from the RGB of its points: the mean RGB, and a name by hue.

The name follows PITT's colour service (hue bins red / yellow / green / blue / pink, a colour
wins only with a strict plurality) with the fix the reference recommends: pixels with low
saturation or value (grey, white, black) are not counted, so grey is no longer "red".

>>> colour_name(np.array([[0.9, 0.1, 0.1], [0.8, 0.2, 0.1]]))
'red'
>>> colour_name(np.array([[0.5, 0.5, 0.5]])) is None
True
"""

from __future__ import annotations

import numpy as np

from shapes.types import FloatArray, Vec3, vec3

__all__ = ["HUE_BINS", "colour_name", "mean_colour"]

# (name, lowest hue, highest hue) in degrees; red wraps around 0.
HUE_BINS: tuple[tuple[str, float, float], ...] = (
    ("red", 320.0, 40.0),
    ("yellow", 40.0, 80.0),
    ("green", 80.0, 160.0),
    ("blue", 160.0, 280.0),
    ("pink", 280.0, 320.0),
)


def mean_colour(colours: FloatArray) -> Vec3:
    """The mean RGB of ``(N, 3)`` colours in [0, 1]."""
    return vec3(colours.mean(axis=0))


def _hsv(rgb: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray]:
    mx, mn = rgb.max(axis=1), rgb.min(axis=1)
    delta = mx - mn
    safe = np.where(delta > 0, delta, 1.0)
    r, g, b = rgb[:, 0], rgb[:, 1], rgb[:, 2]
    hue = np.select(
        [mx == r, mx == g],
        [((g - b) / safe) % 6.0, (b - r) / safe + 2.0],
        (r - g) / safe + 4.0,
    )
    hue = np.where(delta > 0, hue * 60.0, 0.0)
    sat = np.where(mx > 0, delta / np.where(mx > 0, mx, 1.0), 0.0)
    return hue, sat, mx


def colour_name(
    colours: FloatArray, *, min_saturation: float = 0.25, min_value: float = 0.15
) -> str | None:
    """The dominant hue name of ``(N, 3)`` RGB colours in [0, 1], or None if none dominates."""
    hue, sat, val = _hsv(np.asarray(colours, dtype=np.float64).reshape(-1, 3))
    keep = (sat > min_saturation) & (val > min_value)
    if not keep.any():
        return None
    h = hue[keep]
    counts = []
    for _name, lo, hi in HUE_BINS:
        inside = (h >= lo) | (h < hi) if lo > hi else (h >= lo) & (h < hi)
        counts.append(int(inside.sum()))
    best = int(np.argmax(counts))
    if sorted(counts)[-2] == counts[best]:
        return None
    return HUE_BINS[best][0]
