"""The fast array reductions give exactly NumPy's values."""

import numpy as np
import pytest

from shapes.arrays import (
    column_max,
    column_min,
    column_span,
    percentiles,
    unique_inverse,
    unique_sorted,
)


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


@pytest.mark.parametrize("seed", range(5))
def test_percentiles_are_numpys_to_the_bit(seed):
    rng = np.random.default_rng(seed)
    for _ in range(400):
        values = rng.normal(size=int(rng.integers(1, 400))) * rng.choice([1e-3, 1.0, 1e3])
        if rng.random() < 0.2:
            values = values.round(1)  # ties, and zeros of both signs
        q = list(rng.choice([0, 0.5, 1, 2, 5, 33.3, 50, 90, 95, 98, 99, 99.5, 100], size=2))
        got = np.array(percentiles(values, q))
        np.testing.assert_array_equal(got, np.percentile(values, q))
        assert got.tobytes() == np.percentile(values, q).tobytes()


@pytest.mark.filterwarnings("ignore:invalid value:RuntimeWarning")  # numpy's, on inf
@pytest.mark.parametrize(
    "values",
    [[1.0, np.nan, 2.0], [1.0, np.inf, 2.0], [-np.inf, 0.0, 1.0], [-0.0, -0.0], [5.0]],
)
def test_percentiles_of_nan_inf_and_zeros_are_numpys(values):
    q = [0, 50, 99, 100]
    expected = np.percentile(np.array(values), q)
    assert np.array(percentiles(np.array(values), q)).tobytes() == expected.tobytes()


@pytest.mark.parametrize(
    ("values", "q", "fragment"),
    [
        (np.zeros(0), [50], "non-empty 1-D"),
        (np.zeros((2, 2)), [50], "non-empty 1-D"),
        (np.zeros(3), [101], "between 0 and 100"),
        (np.zeros(3), [-1], "between 0 and 100"),
    ],
)
def test_percentiles_refuse_bad_input(values, q, fragment):
    with pytest.raises(ValueError, match=fragment):
        percentiles(values, q)
