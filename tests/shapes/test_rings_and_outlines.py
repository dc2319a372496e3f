"""Round things on the TUM fr2 desk (tests/data/real_scans/README.md, tuned on since stop 37):
the roll of tape, a ring whose outline the Kinect widens, is one standing cylinder of its
radius whatever the seed; the desk's closed and open round things keep theirs, and its flat
things stay planes. In the sensor's frame, against the hand-measured ground truth
(docs/perception.md, "Rings and outlines: the side wall's cylinder")."""

import json
from pathlib import Path

import numpy as np
import pytest

from shapes import Primitive, ShapeKind
from tests.shapes.real_scans import perceived

SCANS = Path(__file__).parents[1] / "data" / "real_scans"
TRUTH = json.loads((SCANS / "truth.json").read_text())


def _primitive_of(name: str, label: str, seed: int) -> tuple[Primitive, np.ndarray]:
    """The one primitive whose cluster lies within 8 cm of the measured object, and its centre
    in the sensor's frame."""
    result = perceived(name, seed)
    measured = TRUTH[name][label]
    back = np.linalg.inv(result.world_from_sensor)
    seen = [back[:3, :3] @ c + back[:3, 3] for c in result.centroids]
    near = [k for k, c in enumerate(seen) if np.linalg.norm(c - measured["centre"]) < 0.08]
    assert len(near) == 1, [result.primitives[k] for k in near]
    primitive = result.primitives[near[0]]
    return primitive, back[:3, :3] @ np.asarray(primitive.centre) + back[:3, 3]


def _assert_standing_cylinder_of_its_radius(name: str, label: str, seed: int) -> None:
    primitive, centre = _primitive_of(name, label, seed)
    measured = TRUTH[name][label]
    assert primitive.kind is ShapeKind.CYLINDER, primitive
    assert primitive.axis is not None and primitive.axis[2] > 0.94  # within 20 deg of up
    assert np.linalg.norm(centre - measured["centre"]) < 0.03
    assert primitive.radius is not None
    assert abs(primitive.radius - measured["radius_m"]) < 0.25 * measured["radius_m"]


@pytest.mark.parametrize("seed", [0, 1, 2, 3])
@pytest.mark.parametrize("name", ["desk_fr2_tum_0", "desk_fr2_tum_1"])
def test_the_roll_of_tape_is_a_standing_cylinder_of_its_radius_on_every_seed(
    name: str, seed: int
) -> None:
    """Before: a Cylinder of r 6.8-8.9 cm 1.7-4.0 cm off, or planes, depending on the seed (the
    Kinect's widened outline behind the roll's top made a wider cylinder cheaper than its own)."""
    _assert_standing_cylinder_of_its_radius(name, "tape roll", seed)


@pytest.mark.parametrize(
    ("name", "label"),
    [("desk_fr2_tum_0", "left can"), ("desk_fr2_tum_0", "mug"), ("desk_fr2_tum_1", "mug")],
)
def test_the_desks_closed_can_and_open_mug_stay_standing_cylinders(name: str, label: str) -> None:
    _assert_standing_cylinder_of_its_radius(name, label, 0)


@pytest.mark.parametrize(
    ("name", "label"),
    [("desk_fr1_tum_1", "book"), ("desk_fr1_tum_1", "keyboard"), ("desk_fr2_tum_0", "keyboard")],
)
def test_flat_things_stay_planes(name: str, label: str) -> None:
    """Only the side wall's cylinder is scored without the outline's fringe: scored so, every
    cylinder made frame 1's book a flat Cylinder (0.094 against the planes' 0.095)."""
    primitive, _ = _primitive_of(name, label, 0)
    assert primitive.kind is ShapeKind.PLANE, primitive
