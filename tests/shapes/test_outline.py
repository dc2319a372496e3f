"""The outline across the rays, and the kinds a pointed outline refuses under coarse depth."""

from pathlib import Path

import numpy as np
import pytest

from shapes import PerceptionParams, ShapeKind
from shapes.fit import fit_cluster
from shapes.fit.outline import outline_rows, pointed, top_fullness
from shapes.types import SupportPlane

UP = np.array([0.0, 0.0, 1.0])
EYE = np.zeros(3)


def silhouette(width_at, height_m: float, rng: np.random.Generator, sigma_m: float = 0.0):
    """Points 2 m ahead on a 2 mm grid whose rows, from the top down, are ``width_at(depth)``
    wide, each moved along its ray by Gaussian range noise of ``sigma_m``."""
    rows = np.arange(0.0, height_m, 0.002) + 0.001
    out = []
    for d in rows:
        half = width_at(d) / 2
        x = np.arange(-half, half, 0.002) + 0.001
        out.append(np.column_stack((x, np.full(len(x), 2.0), np.full(len(x), -d))))
    pts = np.concatenate(out)
    ranges = np.linalg.norm(pts, axis=1)
    return pts * ((ranges + rng.normal(0.0, sigma_m, len(pts))) / ranges)[:, None]


def test_the_outline_fills_its_top_as_its_kind_does() -> None:
    rng = np.random.default_rng(0)
    r = 0.04
    sphere = silhouette(lambda d: 2 * np.sqrt(max(r * r - (d - r) ** 2, 0.0)), 2 * r, rng)
    cone = silhouette(lambda d: 2 * r * d / 0.1, 0.1, rng)
    cylinder = silhouette(lambda d: 2 * r * min(1.0, np.sqrt(d / 0.01)), 0.1, rng)
    full = {
        kind: top_fullness(outline_rows(points, EYE, UP))
        for kind, points in (("sphere", sphere), ("cone", cone), ("cylinder", cylinder))
    }
    assert 0.72 < full["sphere"] < 0.85, full
    assert full["cone"] < 0.3, full
    assert full["cylinder"] > 0.9, full


def test_range_noise_leaves_the_outline_as_it_was() -> None:
    cone = [
        silhouette(lambda d: 0.08 * d / 0.1, 0.1, np.random.default_rng(1), sigma_m=s)
        for s in (0.0, 0.02)
    ]
    widths = [outline_rows(points, EYE, UP).width_m for points in cone]
    np.testing.assert_allclose(widths[0], widths[1], atol=0.003)


def test_a_pointed_outline_counts_only_under_coarse_depth() -> None:
    cone = outline_rows(
        silhouette(lambda d: 0.08 * d / 0.1, 0.1, np.random.default_rng(2)), EYE, UP
    )
    assert pointed(cone, threshold_m=0.02, coarse_share=0.4, max_fullness=0.6)
    assert not pointed(cone, threshold_m=0.008, coarse_share=0.4, max_fullness=0.6)


def test_an_outline_seen_from_straight_above_has_no_rows() -> None:
    flat = np.column_stack((np.random.default_rng(3).uniform(-0.05, 0.05, (100, 2)), np.ones(100)))
    assert outline_rows(flat, EYE, UP) is None


# Two clusters of the bench's far-left row (seed 20261123; tests/data/far_clusters), cones seen
# from 1.8 m under 3 mm range noise that came out spheres: a wide one (scene 3, r 7.4 cm, 8.2 cm
# tall) and a narrow one (scene 9, r 3.5 cm, 12 cm tall) whose rival along the rays was a
# standing cylinder. Their outlines close to a point; fitted as the pipeline fits them (the
# cluster's noise, its frame's generator), both are cones.
FAR_CLUSTERS = Path(__file__).parents[1] / "data" / "far_clusters" / "far_left_cones.npz"


@pytest.mark.parametrize("scene", [3, 9])
def test_far_cones_whose_outline_is_pointed_are_cones(scene: int) -> None:
    data = np.load(FAR_CLUSTERS)
    normal = data[f"scene{scene}_support"]
    fit = fit_cluster(
        data[f"scene{scene}_points"],
        support=SupportPlane(tuple(normal[:3]), float(normal[3])),
        params=PerceptionParams().fit.for_noise(float(data[f"scene{scene}_noise_m"])),
        rng=np.random.default_rng([scene, 0]),
        viewpoint=data[f"scene{scene}_viewpoint"],
    )
    assert fit is not None
    assert fit.primitive.kind is ShapeKind.CONE, fit.costs
