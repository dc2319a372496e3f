"""Cylinder or cone under range noise: a standing object's taper decides when costs tie."""

import numpy as np
import pytest

from shapes import Perception, ShapeKind
from shapes.fit.select import standing_taper
from shapes.sensor import DepthCamera, SensorModel, look_at
from shapes.synthetic import TabletopScene, TruthObject
from shapes.types import SupportPlane

TABLE = SupportPlane((0.0, 0.0, 1.0), 0.0)


def side_points(rng: np.random.Generator, r_bottom: float, r_top: float, sigma: float):
    """A standing surface of revolution seen from one side (half its circumference), 12 cm
    tall, with its radius going linearly from ``r_bottom`` to ``r_top``, radial noise sigma."""
    h = rng.uniform(0.0, 0.12, 600)
    a = rng.uniform(-1.4, 1.4, 600)
    r = r_bottom + (r_top - r_bottom) * h / 0.12 + rng.normal(0.0, sigma, 600)
    return np.column_stack((r * np.sin(a), -r * np.cos(a), h))


@pytest.mark.parametrize("seed", range(3))
def test_a_noisy_cylinder_has_no_taper_and_a_cone_has_its_own(seed: int) -> None:
    rng = np.random.default_rng(seed)
    drop, spread = standing_taper(side_points(rng, 0.04, 0.04, 0.008), TABLE, 0.01) or (0, 0)
    assert abs(drop) < 0.4 * spread
    drop, spread = standing_taper(side_points(rng, 0.05, 0.02, 0.008), TABLE, 0.01) or (0, 0)
    # 3 cm over 12 cm, of which the side below the top's cut spans about 10 cm: 2.5 cm,
    # a little less from the circle fitted to all heights at once.
    assert drop > 0.4 * spread and 0.015 < drop < 0.03


def test_too_few_side_points_give_no_taper() -> None:
    points = side_points(np.random.default_rng(0), 0.04, 0.04, 0.0)[:15]
    assert standing_taper(points, TABLE, 0.01) is None


# A camera 1.7 m from the table's middle, off to one side: under 3 mm noise (about 9 mm at that
# range) the costs of cylinder and cone tie for standing objects.
FAR = DepthCamera(world_from_camera=look_at((0.3, -1.4, 0.9), (0.0, 0.1, 0.0)))
OBJECTS = (
    TruthObject("Cylinder", (-0.2, 0.25, 0.0), radius=0.046, height=0.123),
    TruthObject("Cone", (0.0, 0.3, 0.0), radius=0.041, height=0.131),
    TruthObject("Cylinder", (0.2, 0.25, 0.0), radius=0.051, height=0.127),
    TruthObject("Cone", (-0.15, -0.05, 0.0), radius=0.031, height=0.123),
    TruthObject("Cylinder", (0.15, -0.05, 0.0), radius=0.047, height=0.107),
)


def test_standing_cylinders_and_cones_seen_from_far_under_3_mm_noise_are_not_swapped() -> None:
    """Seeds 2 and 6 made the third cylinder a cone before the taper decided (its cone cost was
    0.016 lower). Spheres taken for these objects are another cause, not counted here."""
    noisy = SensorModel(sigma_1m=0.003)
    swapped = []
    for seed in (0, 2, 6):
        shot = FAR.shoot(TabletopScene(OBJECTS), np.random.default_rng(seed), noisy)
        result = Perception(seed=seed).process(shot.frame)
        for obj in OBJECTS:
            kinds = [
                p.kind
                for p, c in zip(result.primitives, result.centroids, strict=True)
                if np.linalg.norm(c[:2] - np.asarray(obj.position[:2])) < 0.05
            ]
            other = ShapeKind.CONE if obj.kind == "Cylinder" else ShapeKind.CYLINDER
            if other in kinds:
                swapped.append((seed, obj.kind, obj.position))
    assert swapped == []


def test_the_far_cylinder_seen_under_3_mm_noise_stands() -> None:
    """Seed 0's cylinder at (0.2, 0.25): the free cylinder search, its axes drawn from noisy
    normals, found only a lying cylinder (cost 0.102), where the upright one costs about 0.06.
    The support's normal is now a hypothesis of its own."""
    obj = OBJECTS[2]
    shot = FAR.shoot(TabletopScene(OBJECTS), np.random.default_rng(0), SensorModel(sigma_1m=0.003))
    result = Perception(seed=0).process(shot.frame)
    found = [
        p
        for p, c in zip(result.primitives, result.centroids, strict=True)
        if np.linalg.norm(c[:2] - np.asarray(obj.position[:2])) < 0.05
    ]
    assert [p.kind for p in found] == [ShapeKind.CYLINDER]
    assert found[0].axis is not None and abs(found[0].axis[2]) > np.cos(np.radians(10))
    assert found[0].radius is not None and abs(found[0].radius - obj.radius) < 0.01


# Seen from 1.8 m off to the left under 3 mm noise (a selection threshold near 4 cm), short
# standing objects lose their bottom few centimetres with the table: the top cut of the taper,
# the threshold, then left too little of a cone's side to show its slope (seed 7's far-left row
# of bench/perception.py, scene 1, whose objects these are).
FAR_LEFT = DepthCamera(world_from_camera=look_at((-0.4, -1.5, 1.0), (0.0, 0.1, 0.0)))
SHORT_CONES = (
    TruthObject("Cone", (0.268, 0.248, 0.0), radius=0.0525, height=0.0907),
    TruthObject("Cone", (-0.3, 0.165, 0.0), radius=0.0592, height=0.0849),
    TruthObject("Cylinder", (-0.114, -0.021, 0.0), radius=0.0298, height=0.1435),
    TruthObject("Cylinder", (-0.179, -0.203, 0.0), radius=0.0216, height=0.1543),
)


def test_short_far_cones_keep_side_enough_for_their_taper() -> None:
    """Before the cut was held to 40 % of the visible height, seeds 0-5 gave four of the twelve
    cones as Cylinders; the cylinders stay Cylinders."""
    found = []
    for seed in range(6):
        shot = FAR_LEFT.shoot(
            TabletopScene(SHORT_CONES), np.random.default_rng(seed), SensorModel(sigma_1m=0.003)
        )
        result = Perception(seed=seed).process(shot.frame)
        for obj in SHORT_CONES:
            found.append(
                [
                    p.kind.value
                    for p, c in zip(result.primitives, result.centroids, strict=True)
                    if np.linalg.norm(c[:2] - np.asarray(obj.position[:2])) < 0.06
                ]
            )
    assert found == [[obj.kind] for obj in SHORT_CONES] * 6
