"""Faces charged for their parameters (``shapes.fit.select``, docs/perception.md, "Faces
charged for their parameters (stop 40)"): the TUM fr2 desk's left can, whose two vertical faces
and lid cost within 0.02 of its cylinder, comes out a standing cylinder of its radius on every
seed, and its flat things stay planes. In the sensor's frame, against the hand-measured ground
truth (tests/data/real_scans/README.md)."""

import json
from pathlib import Path

import numpy as np
import pytest

from shapes import ShapeKind
from shapes.fit.information import parameter_charges
from tests.shapes.real_scans import perceived

SCANS = Path(__file__).parents[1] / "data" / "real_scans"
TRUTH = json.loads((SCANS / "truth.json").read_text())


def _kind_radius_error(name: str, label: str, seed: int) -> tuple[ShapeKind, float, float]:
    """The one primitive within 8 cm of the measured object: its kind, radius and the distance
    from its centre (a curved one's) or its cluster's centroid (a plane's) to the measured
    centre."""
    result = perceived(name, seed)
    measured = np.asarray(TRUTH[name][label]["centre"])
    back = np.linalg.inv(result.world_from_sensor)
    seen = [back[:3, :3] @ c + back[:3, 3] for c in result.centroids]
    near = [k for k, c in enumerate(seen) if np.linalg.norm(c - measured) < 0.08]
    assert len(near) == 1, [result.primitives[k] for k in near]
    primitive = result.primitives[near[0]]
    centre = seen[near[0]]
    if primitive.kind is not ShapeKind.PLANE:
        centre = back[:3, :3] @ np.asarray(primitive.centre) + back[:3, 3]
    return primitive.kind, primitive.radius or 0.0, float(np.linalg.norm(centre - measured))


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_the_fr2_desks_left_can_is_a_cylinder_of_its_radius_on_every_seed(seed: int) -> None:
    """Before: planes 3.1 cm off on seeds 0 and 2 (two vertical faces and the lid, 0.012 under
    the cylinder's cost on seed 0)."""
    kind, radius, error = _kind_radius_error("desk_fr2_tum_1", "left can", seed)
    assert kind is ShapeKind.CYLINDER
    assert abs(radius / TRUTH["desk_fr2_tum_1"]["left can"]["radius_m"] - 1) <= 0.25
    assert error < 0.03


@pytest.mark.parametrize("label", ["keyboard", "book", "telephone", "monitor"])
def test_the_fr2_desks_flat_things_stay_planes(label: str) -> None:
    kind, _, error = _kind_radius_error("desk_fr2_tum_1", label, 0)
    assert kind is ShapeKind.PLANE
    assert error < 0.03


def test_three_faces_pay_more_than_a_cylinder_and_one_face_less() -> None:
    charges = parameter_charges(3, 300, charge=1.0, noise_factor=3.0)
    assert charges[ShapeKind.PLANE] > charges[ShapeKind.CYLINDER] > charges[ShapeKind.SPHERE]
    one_face = parameter_charges(1, 300, charge=1.0, noise_factor=3.0)
    assert one_face[ShapeKind.PLANE] < one_face[ShapeKind.SPHERE]
    assert parameter_charges(3, 300, charge=0.0, noise_factor=3.0)[ShapeKind.PLANE] == 0.0


@pytest.mark.parametrize(("points", "noise_factor"), [(1, 3.0), (300, 0.0), (300, float("nan"))])
def test_too_few_points_or_no_noise_factor_is_refused(points: int, noise_factor: float) -> None:
    with pytest.raises(ValueError, match="points, noise_factor"):
        parameter_charges(3, points, charge=1.0, noise_factor=noise_factor)
