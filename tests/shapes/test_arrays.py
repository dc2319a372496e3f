"""The fast array reductions give exactly NumPy's values."""

import numpy as np
import pytest

from shapes.arrays import column_max, column_min, column_span, unique_inverse, unique_sorted


@pytest.mark.parametrize("seed", range(5))
def test_column_extremes_are_numpys(seed):
    rng = np.random.default_rng(seed)
    a = rng.normal(size=(int(rng.integers(1, 500)), int(rng.integers(1, 5))))
    a[rng.random(a.shape) < 0.01] = np.nan
    for ours, theirs in ((column_min, a.min(axis=0)), (column_max, a.max(axis=0))):
        np.testing.assert_array_equal(ours(a), theirs)
    np.testing.assert_array_equal(column_span(a), np.ptp(a, axis=0))
    keys = rng.integers(-3, 4, size=(50, 3))
    np.testing.assert_array_equal(column_min(keys), keys.min(axis=0))
    assert column_min(keys).dtype == keys.dtype


@pytest.mark.parametrize("seed", range(5))
def test_unique_keys_are_numpys(seed):
    rng = np.random.default_rng(seed)
    keys = rng.integers(-100, int(rng.integers(1, 10_000)), size=int(rng.integers(1, 5_000)))
    values, index, counts = np.unique(keys, return_inverse=True, return_counts=True)
    ours = unique_inverse(keys)
    for got, expected in zip(ours, (values, index, counts), strict=True):
        np.testing.assert_array_equal(got, expected)
    np.testing.assert_array_equal(unique_sorted(keys), values)


def test_no_rows_is_refused():
    with pytest.raises(ValueError):
        column_min(np.zeros((0, 3)))
