"""Normals in closed form agree with LAPACK's eigenvectors."""

import numpy as np

from shapes.normals import smallest_axes


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
