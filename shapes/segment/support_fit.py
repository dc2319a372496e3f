"""The support's plane measured once more, over its whole main piece, with the depth noise model.

The plane search (:mod:`shapes.segment.planes`) refits each RANSAC plane by plain least squares
on its voxels: every voxel weighs the same, whether it lies 0.8 m or 3.5 m away, though a depth
camera's noise grows with the square of the range (``sigma_1m z²``). On a support seen from 2
to 4 m the far rows, noisier and in depth terraces, tilt the plane, and its height extrapolated
to the camera was 2-6 cm off (docs/perception.md, "The support measured again, weighed by the
depth noise (stop 41)").

:func:`measured_support` fits the plane again through the support's main piece by iteratively
reweighted least squares: each voxel weighs ``1 / sigma²``, with ``sigma`` a third of its
tolerance (the one the plane search already gives it, ``max(support_threshold_m,
3 sigma_1m z²)``), times Tukey's biweight of its residual in units of ``sigma``, so that what
stands on the support within the tolerance band does not pull the plane. Segmentation does not
use this plane: its clusters are cut, and their objects fitted, with the plane search's plane;
this one is the support reported (:attr:`shapes.segment.Segmentation.support`).

>>> rng = np.random.default_rng(0)
>>> xy = rng.uniform(-1.0, 1.0, (2000, 2))
>>> sigma = np.where(xy[:, 0] > 0, 0.02, 0.002)  # the far half ten times as noisy
>>> table = np.column_stack((xy, 0.1 * xy[:, 0] * (xy[:, 0] > 0) + rng.normal(0, sigma)))
>>> coarse = SupportPlane(vec3(np.array([0.0, 0.0, 1.0])), 0.0)
>>> fine = measured_support(coarse, table, 3 * sigma)
>>> bool(abs(fine.signed_distance(np.array([[-0.5, 0.0, 0.0]]))[0]) < 0.002)
True
"""

from __future__ import annotations

import numpy as np

from shapes.types import FloatArray, SupportPlane, vec3

__all__ = ["measured_support"]

_BIWEIGHT = 4.685
"""Tukey's biweight constant, in units of the noise's sigma: 95 % efficiency on Gaussian
noise."""

_ITERATIONS = 10
"""At most this many reweighting rounds; it stops earlier once the plane moves less than
``_SETTLED_M`` anywhere within 5 m (3 to 7 rounds on the tuned-on Kinect scans' supports)."""

_SETTLED_M = 1e-4
"""A tenth of a millimetre: a two-hundredth of the 2 cm the support's height is judged by."""

_MOST_VOXELS = 4000
"""A support of more voxels is measured on an even sample of this many (every k-th voxel): a
floor of 25,000 voxels fixes its plane no better than a table's 4,000, for five times the
CPU."""


def measured_support(
    support: SupportPlane, table: FloatArray, tolerance: FloatArray
) -> SupportPlane:
    """``support`` fitted again through ``table`` (its main piece's voxels, in the world frame)
    by noise-weighted, robust least squares (the module doc), on every k-th voxel when there
    are more than ``_MOST_VOXELS``; ``tolerance``: per voxel, how far from a plane it may lie
    (three times its depth noise).

    The normal keeps the side of ``support``'s; the centre is ``support``'s (the mean of its
    points, unweighted) dropped onto the new plane, and the extent is ``support``'s.
    ``support`` itself is returned when fewer than three voxels keep a weight or they span no
    plane.
    """
    step = max(1, -(-len(table) // _MOST_VOXELS))  # ceil: at most _MOST_VOXELS voxels
    table, tolerance = table[::step], np.asarray(tolerance)[::step]
    normal = np.asarray(support.normal, dtype=np.float64)
    offset = float(support.offset)
    sigma = np.asarray(tolerance, dtype=np.float64) / 3.0
    precision = 1.0 / sigma**2
    for _ in range(_ITERATIONS):
        u = (table @ normal + offset) / (_BIWEIGHT * sigma)
        weight = np.where(np.abs(u) < 1.0, (1.0 - u**2) ** 2, 0.0) * precision
        if np.count_nonzero(weight) < 3:
            return support
        centre = weight @ table / weight.sum()
        spread = table - centre
        scatter = spread.T @ (spread * weight[:, None])
        values, vectors = np.linalg.eigh(scatter)
        if values[1] <= 1e-12 * values[2]:
            return support
        new = vectors[:, 0] if vectors[:, 0] @ normal >= 0 else -vectors[:, 0]
        new_offset = -float(new @ centre)
        moved = abs(new_offset - offset) + 5.0 * float(np.linalg.norm(new - normal))
        normal, offset = new, new_offset
        if moved < _SETTLED_M:
            break
    mean = table.mean(axis=0) if support.centre is None else np.asarray(support.centre)
    on_plane = mean - (mean @ normal + offset) * normal
    return SupportPlane(vec3(normal), offset, vec3(on_plane), support.extent)
