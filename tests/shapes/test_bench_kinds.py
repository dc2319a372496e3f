"""``bench/perception.py`` scores the type target on every object whose kind the ground truth
records (one of the four shapes), and on nothing else; and the ground truth records kinds only
where ``measure.py``'s ``KINDS`` says what an object is."""

import json

import numpy as np
import pytest

from shapes import FrameResult, Primitive, ShapeKind
from tests.shapes.real_scans import SCANS, bench_module, measure_module

TRUTH = json.loads((SCANS / "truth.json").read_text())


def _result(*found: tuple[tuple[float, float, float], Primitive]) -> FrameResult:
    """A frame's result with the identity pose: each primitive's cluster centroid beside it."""
    return FrameResult(
        index=0,
        stamp=None,
        support=None,
        primitives=tuple(prim for _, prim in found),
        events=(),
        centroids=tuple(np.asarray(centroid, dtype=float) for centroid, _ in found),
    )


MADE_UP_TRUTH = {
    "support": {},
    "held_out": False,
    "can": {"centre": [0.0, 0.0, 1.0], "radius_m": 0.03, "kind": "Cylinder"},
    "far cup": {"centre": [0.3, 0.0, 1.0], "kind": "Cylinder"},
    "book": {"centre": [0.6, 0.0, 1.0], "kind": "Plane"},
    "paper": {"centre": [0.9, 0.0, 1.0], "kind": "Plane"},
    "box": {"centre": [-0.3, 0.0, 1.0]},
}
"""Five objects: four of known kind (a round can with its radius, a far cup, a book, a sheet of
paper that will be missed) and a box, none of the four."""


def _plane(at: tuple[float, float, float]) -> Primitive:
    return Primitive(ShapeKind.PLANE, centre=at, axis=(0.0, 0.0, -1.0), hessian_offset=1.0)


def _cylinder(at: tuple[float, float, float], radius_m: float) -> Primitive:
    return Primitive(ShapeKind.CYLINDER, centre=at, axis=(0.0, -1.0, 0.0), radius=radius_m)


@pytest.mark.parametrize(
    ("can_radius_m", "far_cup", "right", "misses"),
    [
        # The can's radius within 25 %, the far cup a Plane, the paper missed.
        (0.035, "Plane", 2, ["far cup: Plane (Cylinder)", "paper: missed (Plane)"]),
        # The far cup a Cylinder too: three right.
        (0.035, "Cylinder", 3, ["paper: missed (Plane)"]),
        # The can a Cylinder of radius 4 cm against 3: the right kind, not the right size.
        (0.04, "Cylinder", 2, ["can: Cylinder r 4.0/3.0 cm (Cylinder)", "paper: missed (Plane)"]),
    ],
)
def test_the_kind_is_scored_for_the_objects_of_known_kind_alone(
    can_radius_m: float, far_cup: str, right: int, misses: list[str]
) -> None:
    cup_at = (0.31, 0.0, 1.0)
    cup = _plane(cup_at) if far_cup == "Plane" else _cylinder(cup_at, 0.04)
    result = _result(
        ((0.0, 0.0, 1.0), _cylinder((0.0, 0.0, 1.0), can_radius_m)),
        (cup_at, cup),
        ((0.6, 0.01, 1.0), _plane((0.6, 0.01, 1.0))),
        ((-0.3, 0.0, 1.0), _cylinder((-0.3, 0.0, 1.0), 0.05)),  # the box: any kind will do
    )
    named: list[str] = []
    _, tally = bench_module("perception")._objects_row(result, MADE_UP_TRUTH, named)
    assert (tally["kinds"], tally["kind right"]) == (4, right)
    assert named == misses
    assert (tally["round"], tally["round right"]) == (1, can_radius_m < 0.0375)
    assert tally["missed"] == 1 and tally["objects"] == 5


def test_the_ground_truth_s_kinds_are_measure_py_s_table() -> None:
    """Every kind in truth.json comes from ``KINDS``, each names a measured object, and is one
    of the four shapes."""
    measure = measure_module()
    recorded = {
        (scan, label): item["kind"]
        for scan, objects in TRUTH.items()
        for label, item in objects.items()
        if isinstance(item, dict) and "kind" in item
    }
    assert recorded == measure.KINDS
    assert set(recorded.values()) <= {kind.value for kind in ShapeKind}
