"""The synthetic tabletop generator: seeded, single-view, with ground truth."""

import numpy as np
import pytest

from shapes import Primitive, ShapeKind
from shapes.synthetic import NO_NOISE, NoiseModel, TabletopScene, TruthObject, random_scene


def test_the_same_seed_gives_the_same_cloud():
    a = random_scene(np.random.default_rng(3), 4).render(np.random.default_rng(4))
    b = random_scene(np.random.default_rng(3), 4).render(np.random.default_rng(4))
    np.testing.assert_array_equal(a.frame.points, b.frame.points)
    np.testing.assert_array_equal(a.frame.colours, b.frame.colours)


def test_only_the_side_facing_the_camera_is_seen():
    scene = TabletopScene((TruthObject("Sphere", (0.0, 0.0, 0.0), radius=0.06, height=0.12),))
    shot = scene.render(np.random.default_rng(0), NO_NOISE)
    pts = shot.frame.world_points()[shot.labels == 0]
    centre = np.array(scene.objects[0].centre)
    eye = scene.camera.world_from_camera[:3, 3]
    outward = (pts - centre) / 0.06
    np.testing.assert_allclose(np.linalg.norm(pts - centre, axis=1), 0.06, atol=1e-9)
    assert ((outward * (eye - pts)).sum(axis=1) > -1e-9).all()  # no point on the far side
    assert len(pts) > 500


def test_depth_noise_follows_the_kinect_model():
    scene = TabletopScene(())
    exact = scene.render(np.random.default_rng(0), NO_NOISE).frame.world_points()
    np.testing.assert_allclose(exact[:, 2], 0.0, atol=1e-12)  # the bare table
    frame = scene.render(np.random.default_rng(0)).frame
    rays = frame.points / frame.points[:, 2:3]  # camera-frame rays with unit depth
    pose = frame.world_from_sensor
    true_depth = -pose[2, 3] / (rays @ pose[:3, :3].T)[:, 2]  # where each ray meets the table
    z = (frame.points[:, 2] - true_depth) / NoiseModel().sigma(true_depth)
    robust_sigma = 1.4826 * np.median(np.abs(z - np.median(z)))  # flying pixels ignored
    assert 0.95 < robust_sigma < 1.05


def test_scenes_place_objects_apart_and_report_truth_in_primitive_terms():
    scene = random_scene(np.random.default_rng(8), 6)
    assert len(scene.objects) == 6
    cone = TruthObject("Cone", (0.1, 0.2, 0.0), radius=0.05, height=0.12)
    assert cone.centre == (0.1, 0.2, 0.03) and cone.apex == (0.1, 0.2, 0.12)
    assert TruthObject("Box", (0, 0, 0), size=(0.1, 0.1, 0.1)).expected_kind is ShapeKind.PLANE


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        ({"n_objects": -1}, "n_objects: expected a count >= 0"),
        ({"kinds": ("Torus",)}, "kinds: expected names"),
    ],
)
def test_bad_scene_requests_are_refused(kwargs, message):
    with pytest.raises(ValueError, match=message):
        random_scene(np.random.default_rng(0), **{"n_objects": 2, **kwargs})


def test_attributes_use_the_ontology_names():
    p = Primitive(
        ShapeKind.CYLINDER,
        centre=(0.1, 0.2, 0.3),
        axis=(0.0, 0.0, 1.0),
        radius=0.04,
        height=0.1,
        point_on_axis=(0.1, 0.2, 0.25),
        colour=(1.0, 0.0, 0.0),
        tracking_id=4,
    )
    assert p.attributes() == {
        "centreX": 0.1,
        "centreY": 0.2,
        "centreZ": 0.3,
        "axisX": 0.0,
        "axisY": 0.0,
        "axisZ": 1.0,
        "radius": 0.04,
        "height": 0.1,
        "pointOnAxisX": 0.1,
        "pointOnAxisY": 0.2,
        "pointOnAxisZ": 0.25,
        "colourR": 1.0,
        "colourG": 0.0,
        "colourB": 0.0,
        "trackingId": 4,
    }
    assert ShapeKind.CYLINDER.value == "Cylinder"
