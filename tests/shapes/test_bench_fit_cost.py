"""``bench/perception_fit_cost.py`` replays a recorded fit exactly: the generator is copied
whole, with the count of the children it has spawned (the standing cylinder's draws come from
a spawned generator), not only its bit generator's state."""

import copy

import numpy as np

from shapes.fit import fit_cluster
from shapes.types import SupportPlane
from tests.shapes.real_scans import bench_module


def _standing_cylinder(rng: np.random.Generator) -> np.ndarray:
    angle = rng.uniform(0, np.pi, 800)
    height = rng.uniform(0.0, 0.12, 800)
    side = np.column_stack((0.04 * np.cos(angle), 0.04 * np.sin(angle), height))
    return side + rng.normal(0, 0.001, side.shape)


def test_a_replayed_fit_is_the_fit_of_the_recorded_generator() -> None:
    bench = bench_module("perception_fit_cost")
    points = _standing_cylinder(np.random.default_rng(3))
    rng = np.random.default_rng([0, 1])
    rng.spawn(1)  # a generator that has spawned before: the next spawn is its second child
    call = {
        "points": points,
        "rng": copy.deepcopy(rng),
        "support": SupportPlane((0.0, 0.0, 1.0), 0.0),
        "params": None,
        "viewpoint": None,
    }
    fit = fit_cluster(points, support=call["support"], rng=rng)
    assert fit is not None
    _, replayed = bench._run(fit_cluster, call)
    _, again = bench._run(fit_cluster, call)
    assert replayed == again
    _, direct = bench._run(lambda *a, **kw: fit, call)  # the chain's own fit, as _run reports it
    assert replayed == direct
