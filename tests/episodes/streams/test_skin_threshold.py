"""The skin filter with the paper's threshold θ beside the lossless mode (issue 16 item 5)."""

from pathlib import Path

import numpy as np
import pytest

from episodes.streams import InvalidSampleError, Recorder, Replayer, export_bag

TAXELS = 384
THETA = 0.5


def _skin(rng: np.random.Generator, frames: int) -> list[np.ndarray]:
    """Skin at rest jittering within ±0.2 of its baseline 10, touched (30) on frames 5-7."""
    out = []
    for i in range(frames):
        value = (10.0 + rng.uniform(-0.2, 0.2, TAXELS)).astype(np.float32)
        if 5 <= i <= 7:
            value[40:60] = 30.0
        out.append(value)
    return out


def _record(path: Path, values: list[np.ndarray], **settings: object) -> Path:
    rec = Recorder(path, episode_id=path.name)
    rec.add_provider("skin", "float_array", dtype="float32", shape=[TAXELS], **settings)
    for i, value in enumerate(values):
        rec.tick({"skin": value}, time_ns=(i + 1) * 10_000_000)
    rec.close()
    return path


def _size(path: Path) -> int:
    return sum(f.stat().st_size for f in path.glob("*.mcap"))


def test_jitter_within_theta_is_stored_as_the_baseline(tmp_path: Path) -> None:
    values = _skin(np.random.default_rng(16), 200)
    dense = _record(tmp_path / "dense", values)
    lossless = _record(tmp_path / "lossless", values, baseline=10.0)
    bounded = _record(tmp_path / "bounded", values, baseline=10.0, threshold=THETA)
    # the lossless filter cannot drop jitter, so it stores more than no filter; θ drops it
    assert _size(lossless) > _size(dense)
    assert _size(bounded) * 4 < _size(dense)
    replayed = [f.samples["skin"].value for f in Replayer(bounded).frames()]
    assert len(replayed) == len(values)
    for got, sent in zip(replayed, values, strict=True):
        assert np.all(np.abs(got - sent) <= THETA)  # the bound holds everywhere
        touched = sent == 30.0
        assert np.array_equal(got[touched], sent[touched])  # beyond θ: exact
        assert np.all(got[~touched] == 10.0)  # within θ: the baseline
    exact = [f.samples["skin"].value for f in Replayer(lossless).frames()]
    assert all(np.array_equal(g, s) for g, s in zip(exact, values, strict=True))


def test_the_bound_is_recorded_with_the_stream_and_survives_export(tmp_path: Path) -> None:
    path = _record(
        tmp_path / "ep", _skin(np.random.default_rng(1), 10), baseline=10.0, threshold=THETA
    )
    spec = Replayer(path).providers["skin"]
    assert spec.threshold == THETA and spec.config()["threshold"] == THETA
    export_bag(path, tmp_path / "out")
    assert len(list(Replayer(tmp_path / "out").frames())) == 10


def test_nan_is_never_taken_for_the_baseline(tmp_path: Path) -> None:
    value = np.full(TAXELS, 10.0, dtype=np.float32)
    value[3] = np.nan
    path = _record(tmp_path / "ep", [value], baseline=10.0, threshold=THETA)
    (frame,) = Replayer(path).frames()
    assert np.isnan(frame.samples["skin"].value[3])


@pytest.mark.parametrize(
    ("settings", "fragment"),
    [
        ({"baseline": 10.0, "threshold": -1}, "threshold: got -1"),
        ({"baseline": 10.0, "threshold": float("inf")}, "threshold: got inf"),
        ({"threshold": 0.5}, "a baseline to compare with"),
        ({"baseline": 10.0, "threshold": True}, "threshold: got True"),
    ],
)
def test_bad_thresholds_are_refused(tmp_path: Path, settings: dict, fragment: str) -> None:
    rec = Recorder(tmp_path / "ep", episode_id="ep")
    with pytest.raises(InvalidSampleError) as info:
        rec.add_provider("skin", "float_array", shape=[TAXELS], **settings)
    assert fragment in str(info.value)
    rec.close()
