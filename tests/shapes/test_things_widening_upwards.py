"""A standing thing that widens upwards (a flower pot, a paper cup) is no cone standing on its
tip under the support: its primitive lies where its points are (shapes/fit/select.py, "Standing
and widening upwards")."""

import numpy as np
import pytest

from shapes.fit.select import FitParams, fit_cluster
from shapes.types import ShapeKind, SupportPlane


def _pot(seed: int, widening: float) -> np.ndarray:
    """A pot 12 cm tall standing on z = 0, 3.2 cm in radius at the bottom and ``widening`` m
    wider per metre up, seen from one side (its near wall from 1 cm up, the bottom centimetre
    left with the table) and over its rim (the far wall's inside from 9 cm up), 1 mm noise."""
    rng = np.random.default_rng(seed)
    h = np.concatenate((rng.uniform(0.01, 0.12, 700), rng.uniform(0.09, 0.12, 200)))
    a = np.concatenate((rng.uniform(-1.4, 1.4, 700), rng.uniform(-1.2, 1.2, 200)))
    side = np.concatenate((-np.ones(700), np.ones(200)))  # near wall, far wall's inside
    r = 0.032 + widening * h
    pot = np.column_stack((r * np.sin(a), side * r * np.cos(a), h))
    return pot + rng.normal(0.0, 0.001, pot.shape)


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_a_pot_widening_upwards_is_fitted_where_it_stands(seed: int) -> None:
    """Before stop 37's merge fix, a cone widening upwards won (its apex 8 cm under the table)
    and its base, put on the support at the apex's end, left it all under the table: its
    centre 4 cm under it."""
    points = _pot(seed, 0.2)
    fit = fit_cluster(
        points,
        support=SupportPlane((0.0, 0.0, 1.0), 0.0),
        params=FitParams(),
        rng=np.random.default_rng(seed),
    )
    assert fit is not None
    primitive = fit.primitive
    assert primitive.kind in (ShapeKind.CYLINDER, ShapeKind.CONE), primitive
    centre = np.asarray(primitive.centre)
    assert 0.0 < centre[2] < 0.12, primitive
    assert np.linalg.norm(centre[:2]) < 0.02, primitive
    if primitive.kind is ShapeKind.CONE:
        assert primitive.apex is not None and primitive.apex[2] > centre[2], primitive
