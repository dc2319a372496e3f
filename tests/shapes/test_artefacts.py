"""Sensor artefacts: noise measured on the image, flying pixels, veils and sparse points."""

import numpy as np
import pytest

from shapes import Frame, Perception, ShapeKind
from shapes.artefacts import depth_noise_1m, flying_pixels, sparse_points, sparse_voxels
from shapes.sensor import DepthCamera, SensorModel
from shapes.synthetic import TabletopScene, TruthObject

CAMERA = DepthCamera().scaled(0.5)
OBJECTS = (
    TruthObject("Sphere", (-0.1, 0.0, 0.0), radius=0.05, height=0.1),
    TruthObject("Cylinder", (0.12, 0.05, 0.0), radius=0.04, height=0.14),
)


@pytest.fixture(scope="module")
def shot():
    """A 320x240 frame with flying pixels at every depth edge (probability 0.5)."""
    return CAMERA.shoot(TabletopScene(OBJECTS), np.random.default_rng(5))


@pytest.mark.parametrize("sigma_1m", [0.001, 0.003, 0.005])
def test_the_depth_noise_is_measured_from_the_image(sigma_1m):
    sensor = SensorModel(sigma_1m=sigma_1m, quantum_1m=0.0, flying_probability=0.0)
    shot = CAMERA.shoot(TabletopScene(OBJECTS), np.random.default_rng(1), sensor)
    assert depth_noise_1m(shot.depth) == pytest.approx(sigma_1m, rel=0.15)


def test_flying_pixels_are_dropped_and_the_surfaces_kept(shot):
    error = np.abs(shot.depth - shot.exact_depth)
    flying = np.isfinite(error) & (error > 0.02)  # mixed depths, far off any surface
    surface = np.isfinite(error) & (error < 0.005)
    drop = flying_pixels(shot.depth, depth_noise_1m(shot.depth), focal_px=CAMERA.fx)
    assert flying.sum() > 100
    assert (drop & flying).sum() > 0.8 * flying.sum()
    assert (drop & surface).sum() < 0.01 * surface.sum()


@pytest.mark.parametrize("step", [2, 3])
def test_flying_pixels_judged_on_a_grid_are_the_full_masks_grid(shot, step):
    full = flying_pixels(shot.depth, depth_noise_1m(shot.depth), focal_px=CAMERA.fx)
    grid = flying_pixels(shot.depth, depth_noise_1m(shot.depth), focal_px=CAMERA.fx, step=step)
    assert full[::step, ::step].sum() > 20
    np.testing.assert_array_equal(grid, full[::step, ::step])


def test_a_step_below_one_is_refused():
    with pytest.raises(ValueError, match="step: expected a positive integer, got 0"):
        flying_pixels(np.ones((4, 4)), 0.001, step=0)


def test_a_veil_along_the_ray_is_dropped():
    # A surface seen almost edge-on: depth grows by 5 cm per pixel across the image.
    depth = 1.0 + 0.05 * np.tile(np.arange(20.0), (20, 1))
    depth[:, :10] = 1.0  # and a flat wall it hangs from
    drop = flying_pixels(depth, 0.001, focal_px=570.0)
    assert drop[:, 11:19].all()
    assert not drop[:, :9].any()


def test_stray_voxels_are_sparse_and_a_surface_is_not():
    grid = np.stack(np.meshgrid(np.arange(10.0), np.arange(10.0), [0.0]), -1).reshape(-1, 3)
    cloud = np.vstack((grid * 0.01, [[0.3, 0.3, 0.3]]))
    sparse = sparse_voxels(cloud, 0.01)
    assert sparse[-1] and not sparse[:-1].any()


def test_an_unorganised_cloud_loses_its_veils_and_keeps_its_shapes(shot):
    # The same frame as a bare world-frame cloud: no image, so only density can tell.
    frame = Frame(shot.frame.world_points())
    kinds = sorted(p.kind for p in Perception().process(frame).primitives)
    assert kinds == [ShapeKind.CYLINDER, ShapeKind.SPHERE]


def test_sparse_points_are_the_ones_off_the_surface():
    rng = np.random.default_rng(2)
    surface = np.column_stack((rng.random((500, 2)) * 0.05, np.zeros(500)))
    veil = np.column_stack((np.full(6, 0.025), np.full(6, 0.025), np.linspace(0.01, 0.06, 6)))
    mask = sparse_points(np.vstack((surface, veil)))
    assert mask[-6:].all() and mask[:-6].sum() < 5
