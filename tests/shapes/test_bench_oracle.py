"""``bench/perception_oracle.py`` takes each measured object's points as the ground truth takes
them and scores the fit on them as ``bench/perception.py`` scores the chain's primitives."""

import json
from pathlib import Path
from types import ModuleType

import numpy as np
import pytest

from shapes import open_source
from tests.shapes.real_scans import SCANS, bench_module, measure_module, perceived

TRUTH = json.loads((SCANS / "truth.json").read_text())


class Loaded(Exception):
    """Raised instead of loading a scan."""


@pytest.fixture(scope="module")
def oracle() -> ModuleType:
    """bench/perception_oracle.py as a module."""
    return bench_module("perception_oracle")


@pytest.mark.parametrize("scan", ["mug_stereo", "bottles_kinect", "desk_tum"])
def test_each_object_s_points_are_the_ground_truth_s(oracle: ModuleType, scan: str) -> None:
    """As many points as truth.json counts, and, where the truth is the visible points'
    centroid, that centroid (desk_tum: heights, boxes and NEARER_THAN_M cuts all matter)."""
    image = measure_module().points_of(scan).reshape(-1, 3)
    for label, pixels in oracle.object_pixels(scan, scan).items():
        item = TRUTH[scan][label]
        assert len(pixels) == item["points"], label
        if "radius_m" not in item:
            np.testing.assert_allclose(image[pixels].mean(axis=0), item["centre"], atol=1e-4)


def _oracle_score(oracle: ModuleType, pixels: dict[str, np.ndarray]) -> object:
    frame = next(open_source(SCANS / "mug_stereo.npz"))
    fits = oracle.oracle_fits(frame, pixels, oracle.measured_support("mug_stereo", "mug_stereo"))
    return oracle.score_object(fits["mug"][0].result, TRUTH["mug_stereo"], "mug")


def test_the_mug_s_own_points_score_as_the_bench_scores_the_chain(oracle: ModuleType) -> None:
    bench_cells, bench_tally = oracle.bench._objects_row(
        perceived("mug_stereo"), TRUTH["mug_stereo"]
    )
    chain = oracle.score_object(perceived("mug_stereo"), TRUTH["mug_stereo"], "mug")
    own = _oracle_score(oracle, oracle.object_pixels("mug_stereo", "mug_stereo"))
    assert bench_tally["one within 3 cm"] == bench_tally["round right"] == 1
    assert chain.cell == bench_cells[0]
    assert (own.outcome, own.round_right) == (chain.outcome, chain.round_right)
    assert own.outcome == "one within 3 cm"


def test_the_bottles_own_points_score_as_the_bench_scores_the_chain(oracle: ModuleType) -> None:
    """Per object the bench's tally, object by object, and the oracle agree on bottles_kinect,
    where the chain finds all three; the bottles' points swapped between two labels are found
    for neither."""
    truth, chain = TRUTH["bottles_kinect"], perceived("bottles_kinect")
    _, tally = oracle.bench._objects_row(chain, truth)
    frame = next(open_source(SCANS / "bottles_kinect.npz"))
    support = oracle.measured_support("bottles_kinect", "bottles_kinect")
    pixels = oracle.object_pixels("bottles_kinect", "bottles_kinect")
    fits = oracle.oracle_fits(frame, pixels, support)
    theirs = [oracle.score_object(chain, truth, label) for label in pixels]
    own = [oracle.score_object(fits[label][0].result, truth, label) for label in pixels]
    assert tally["one within 3 cm"] == len(pixels) == 3
    assert [s.outcome for s in theirs] == [s.outcome for s in own] == ["one within 3 cm"] * 3
    swapped = dict(pixels, detergent=pixels["milk carton"], **{"milk carton": pixels["detergent"]})
    fits = oracle.oracle_fits(frame, swapped, support)
    for label in ("detergent", "milk carton"):
        assert oracle.score_object(fits[label][0].result, truth, label).outcome == "missed"


@pytest.mark.parametrize(
    "rows_cols",
    [
        (390, 470, 150, 300),  # the bare table the support is measured on
        (225, 385, 250, 360),  # the mug's box moved 80 columns left: its left half and table
    ],
)
def test_points_that_are_not_the_mug_s_are_not_found(
    oracle: ModuleType, rows_cols: tuple[int, int, int, int]
) -> None:
    rows, cols = np.mgrid[rows_cols[0] : rows_cols[1], rows_cols[2] : rows_cols[3]]
    wrong = np.sort((rows * 640 + cols).ravel()).astype(np.intp)
    assert _oracle_score(oracle, {"mug": wrong}).outcome != "one within 3 cm"


def test_no_held_out_scan_is_loaded(oracle: ModuleType, monkeypatch: pytest.MonkeyPatch) -> None:
    def refuse(path: object) -> None:
        raise Loaded(Path(str(path)).stem)

    monkeypatch.setattr(oracle, "open_source", refuse)
    monkeypatch.setattr(oracle.measure, "points_of", refuse)
    held_out = {name: name for name, scan in TRUTH.items() if scan["held_out"]}
    assert held_out
    monkeypatch.setattr(oracle.bench, "REAL_TRUTH", held_out)
    oracle.run()
    monkeypatch.setattr(oracle.bench, "REAL_TRUTH", {"mug_stereo": "mug_stereo"})
    with pytest.raises(Loaded, match="mug_stereo"):  # the refusal works
        oracle.run()


def test_points_seen_far_behind_an_object_are_counted(oracle: ModuleType) -> None:
    """Three points at 1 m and one 2 m behind them: one point behind, and without it the
    centroid moves by a quarter of the way to it, in depth and sideways."""
    image = np.array([[[0.0, 0.0, 1.0], [0.0, 0.0, 1.0], [0.0, 0.0, 1.0], [0.4, 0.0, 3.0]]])
    behind, moved = oracle.seen_behind(image, np.arange(4))
    assert behind == 1
    assert moved == pytest.approx(np.hypot(0.1, 0.5))
    assert oracle.seen_behind(image, np.arange(3)) == (0, 0.0)
