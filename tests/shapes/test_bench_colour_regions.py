"""``bench/perception_colour_regions.py`` parts the splitter's clusters by colour without changing
what the chain finds, and traces the fr1 power adapter's merge (docs/perception.md, "Flat things
side by side, parted by colour regions (stop 40, tried)")."""

import re
from types import ModuleType

import numpy as np
import pytest

import shapes.segment.clusters as clusters
import shapes.segment.segmentation as segmentation
from shapes import open_source
from shapes.segment.splitting import split_clusters
from tests.shapes.real_scans import SCANS, bench_module

SCAN = "desk_fr1_tum_0"


@pytest.fixture(scope="module")
def colour_regions() -> ModuleType:
    """bench/perception_colour_regions.py as a module."""
    return bench_module("perception_colour_regions")


@pytest.fixture(scope="module")
def adapter_lines(colour_regions: ModuleType) -> list[str]:
    """The ground truth's partition of the power adapter from its cluster, seed 0."""
    frame = next(open_source(SCANS / f"{SCAN}.npz"))
    pixels = colour_regions.oracle.object_pixels(SCAN, SCAN)
    return [
        line
        for call in colour_regions.run_logged(frame, 0)
        for line in colour_regions.pair_lines(SCAN, 0, call, colour_regions.owners_of(call, pixels))
    ]


def test_the_logged_run_leaves_the_steps_as_they_were(
    colour_regions: ModuleType, adapter_lines: list[str]
) -> None:
    assert clusters.split_clusters is split_clusters
    assert segmentation.clusters_on is clusters.clusters_on


def test_the_adapter_shares_one_uncut_cluster_with_the_dispenser(adapter_lines: list[str]) -> None:
    """Its colour seam is weaker than the dispenser's own, and the union is as good a plane."""
    (line,) = adapter_lines
    assert "cluster of 137 voxels: power adapter 27, tape dispenser 85" in line
    apart = _numbers(r"; dE ([\d.]+);", line)[0]
    inner = _numbers(r"regions ([\d.]+) apart", line)[0]
    assert 40 < apart < inner
    union, *parts = _numbers(r"union ([\d.]+) cm, parts ([\d.]+) and ([\d.]+)", line)
    assert max(parts) > union


def _numbers(pattern: str, line: str) -> list[float]:
    found = re.search(pattern, line)
    assert found is not None, f"{pattern!r} not in {line!r}"
    return [float(group) for group in found.groups()]


def test_two_means_parts_two_colours(colour_regions: ModuleType) -> None:
    colours = np.array([[10.0, 0, 0], [11.0, 0, 0], [60.0, 5, 5], [61.0, 5, 5], [12.0, 0, 0]])
    assert colour_regions.two_means(colours).tolist() == [0, 0, 1, 1, 0]


def test_plane_rms_of_a_flat_square_is_zero(colour_regions: ModuleType) -> None:
    square = np.array([[0.0, 0, 1], [1, 0, 1], [0, 1, 1], [1, 1, 1]])
    assert colour_regions.plane_rms(square) == pytest.approx(0.0, abs=1e-12)
