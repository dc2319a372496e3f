"""Normals in closed form agree with LAPACK's eigenvectors."""

import numpy as np
import pytest

from shapes.normals import patch_normals, smallest_axes


def test_the_closed_form_axis_is_lapacks_smallest_eigenvector():
    rng = np.random.default_rng(0)
    spread = rng.normal(size=(2000, 3, 3)) * [1.0, 1.0, 1e-3]  # flat patches and random ones
    cov = spread @ spread.transpose(0, 2, 1)
    expected = np.linalg.eigh(cov)[1][:, :, 0]
    cosine = np.abs(np.einsum("ni,ni->n", smallest_axes(cov), expected))
    np.testing.assert_allclose(cosine, 1.0, atol=1e-9)


def test_a_line_or_a_point_still_gets_a_unit_axis():
    line = np.zeros((1, 3, 3))
    line[0, 0, 0] = 1.0
    axes = smallest_axes(np.concatenate((line, np.zeros((1, 3, 3)))))
    np.testing.assert_allclose(np.linalg.norm(axes, axis=1), 1.0)
    assert abs(axes[0, 0]) < 1e-12  # normal to the line


@pytest.mark.parametrize("seed", range(3))
def test_patch_normals_are_the_smallest_axes_of_each_patchs_covariance(seed):
    rng = np.random.default_rng(seed)
    points = rng.normal(size=(500, 3)) * (0.05, 0.03, 0.002) + (0.4, -0.2, 1.3)
    neighbours = rng.integers(0, 500, size=(300, 10))
    patches = points[neighbours]
    centred = patches - patches.mean(axis=1, keepdims=True)
    expected = smallest_axes(np.einsum("nki,nkj->nij", centred, centred))
    np.testing.assert_array_equal(patch_normals(points, neighbours), expected)


def test_neighbours_that_are_not_a_table_are_refused():
    with pytest.raises(ValueError, match=r"neighbours: expected an \(N, k\) array"):
        patch_normals(np.zeros((4, 3)), np.arange(4))


def _smallest_axes_with_numpys_cross(cov: np.ndarray) -> np.ndarray:
    """The closed form as first written (stop 36): ``C - lambda I`` as an (N, 3, 3) array, its
    rows' cross products by ``np.cross``; the contract of :func:`smallest_axes` is its values
    to the bit."""
    a00, a11, a22 = cov[:, 0, 0], cov[:, 1, 1], cov[:, 2, 2]
    a01, a02, a12 = cov[:, 0, 1], cov[:, 0, 2], cov[:, 1, 2]
    q = (a00 + a11 + a22) / 3.0
    off = a01 * a01 + a02 * a02 + a12 * a12
    p = np.sqrt(((a00 - q) ** 2 + (a11 - q) ** 2 + (a22 - q) ** 2 + 2.0 * off) / 6.0)
    safe = np.where(p > 0, p, 1.0)
    b00, b11, b22 = (a00 - q) / safe, (a11 - q) / safe, (a22 - q) / safe
    b01, b02, b12 = a01 / safe, a02 / safe, a12 / safe
    half_det = (
        b00 * (b11 * b22 - b12 * b12)
        - b01 * (b01 * b22 - b12 * b02)
        + b02 * (b01 * b12 - b11 * b02)
    ) / 2.0
    phi = np.arccos(np.clip(half_det, -1.0, 1.0)) / 3.0
    smallest = q + 2.0 * p * np.cos(phi + 2.0 * np.pi / 3.0)
    rows = cov - smallest[:, None, None] * np.eye(3)
    candidates = np.stack(
        (
            np.cross(rows[:, 0], rows[:, 1]),
            np.cross(rows[:, 0], rows[:, 2]),
            np.cross(rows[:, 1], rows[:, 2]),
        ),
        axis=1,
    )
    lengths = np.einsum("nki,nki->nk", candidates, candidates)
    best = lengths.argmax(axis=1)
    axis = candidates[np.arange(len(cov)), best]
    norm = np.sqrt(lengths[np.arange(len(cov)), best])
    flat = norm <= 1e-30 * np.maximum(1.0, q * q)
    if flat.any():
        axis[flat] = np.linalg.eigh(cov[flat])[1][:, :, 0]
        norm[flat] = 1.0
    return np.asarray(axis / norm[:, None])


def _awkward_covariances() -> np.ndarray:
    """Random covariances, flat ones, a line, zeros, and zeros of either sign off the diagonal."""
    rng = np.random.default_rng(7)
    spread = rng.normal(size=(3000, 3, 3)) * [1.0, 1.0, 1e-3]
    line = np.zeros((2, 3, 3))
    line[:, 0, 0] = 1.0
    signed = np.zeros((2, 3, 3))
    signed[:, 0, 1] = signed[:, 1, 0] = -0.0
    signed[:, 2, 2], signed[1, 1, 1] = 2.0, 0.5
    return np.concatenate((spread @ spread.transpose(0, 2, 1), line, np.zeros((2, 3, 3)), signed))


def test_smallest_axes_are_the_cross_product_forms_to_the_bit():
    """Speed work (stop 38) wrote the cross products out on contiguous rows: every value, the
    sign of every zero included, is still the one np.cross's form gives."""
    cov = _awkward_covariances()
    expected = _smallest_axes_with_numpys_cross(cov)
    assert smallest_axes(cov).tobytes() == expected.tobytes()
    assert smallest_axes(np.asfortranarray(cov)).tobytes() == expected.tobytes()
    assert smallest_axes(np.zeros((0, 3, 3))).shape == (0, 3)


@pytest.mark.parametrize("k", [1, 10, 30])
def test_patch_normals_are_the_covariance_forms_to_the_bit(k):
    """The covariance summed over (k, N, 3) patches, then its smallest axis: the values
    patch_normals gives from each coordinate gathered apart."""
    rng = np.random.default_rng(k)
    points = rng.normal(size=(800, 3)) * (0.05, 0.03, 0.002) + (0.4, -0.2, 1.3)
    neighbours = rng.integers(0, 800, size=(400, k))
    patches = np.take(points, np.transpose(neighbours), axis=0)
    centred = patches - patches.mean(axis=0)
    cov = np.empty((centred.shape[1], 3, 3))
    for i in range(3):
        for j in range(i, 3):
            cov[:, i, j] = cov[:, j, i] = (centred[:, :, i] * centred[:, :, j]).sum(axis=0)
    expected = _smallest_axes_with_numpys_cross(cov)
    assert patch_normals(points, neighbours).tobytes() == expected.tobytes()
