"""A numeric channel read by one scan of its MCAP file gives exactly what replay gives, and
channels the scan cannot slice (baseline-filtered) are still plotted, through replay."""

from pathlib import Path

import numpy as np
import pytest

from api.views import channels, series
from api.views.series import scan_channel
from episodes.streams import InvalidSampleError, Recorder, Replayer, UnknownProviderError
from episodes.streams.bagwrite import mcap_file
from episodes.streams.mcapread import McapFile

T0 = 1_770_000_000_000_000_000


@pytest.fixture(scope="module", params=[None, "zstd"], ids=["plain", "zstd chunks"])
def recording(tmp_path_factory: pytest.TempPathFactory, request: pytest.FixtureRequest) -> Path:
    path = tmp_path_factory.mktemp("series") / "ep"
    recorder = Recorder(path, episode_id="ep", compression=request.param, flush_interval_s=0.01)
    recorder.add_provider("f64", "float_array", dtype="float64", shape=[3])
    recorder.add_provider("f32", "float_array", dtype="float32", shape=[2, 2])
    recorder.add_provider("arm", "joint_state", names=["shoulder", "elbow", "wrist"])
    recorder.add_provider("still", "float_array", dtype="float64", shape=[2], baseline=[0.0, 0.0])
    recorder.add_provider("words", "string")
    rng = np.random.default_rng(3)
    for i in range(400):
        samples: dict[str, object] = {"f64": rng.normal(size=3), "arm": rng.normal(size=3)}
        if i % 3 == 0:  # a channel in some ticks only
            samples["f32"] = rng.normal(size=(2, 2)).astype(np.float32)
        samples["still"] = np.array([0.0, 0.0]) if i % 4 else np.array([1.0, float(i)])
        if i == 7:
            samples["f64"] = np.array([np.nan, np.inf, -0.0])
            samples["words"] = "hello"
        recorder.tick(samples, time_ns=T0 + i * 10_000_000)
    recorder.close()
    return path


def _replayed(path: Path, channel: str) -> tuple[np.ndarray, np.ndarray]:
    replayer = Replayer(path)
    spec = replayer.providers[channel]
    series = channels._read_series(replayer, channel, spec)
    return series.time_ns, series.values


@pytest.mark.parametrize("channel", ["f64", "f32", "arm"])
def test_the_scan_reads_what_replay_reads(recording: Path, channel: str) -> None:
    assert McapFile.open(mcap_file(recording)).indexed  # read through the file's indexes
    scan = scan_channel(mcap_file(recording), channel)
    assert scan.values is not None and scan.time_ns is not None
    times, values = _replayed(recording, channel)
    np.testing.assert_array_equal(scan.time_ns, times)
    np.testing.assert_array_equal(scan.values.T, values)
    assert scan.start_ns == Replayer(recording).start_ns == T0
    assert len(times) == (134 if channel == "f32" else 400)


def test_a_baseline_filtered_channel_is_left_to_replay_and_still_plotted(
    recording: Path,
) -> None:
    assert scan_channel(mcap_file(recording), "still").values is None
    plot = channels.plot_data(recording, "still", points=2000)
    assert plot.samples == 400
    assert plot.values[0][:5] == [1.0, 0.0, 0.0, 0.0, 1.0]
    assert plot.values[1][4] == 4.0


def test_the_plot_decimates_the_scanned_series_and_keeps_the_errors(recording: Path) -> None:
    channels._cache.clear()
    plot = channels.plot_data(recording, "arm", points=100)
    assert plot.series == ["shoulder position", "elbow position", "wrist position"]
    assert plot.samples == 400 and len(plot.t) == 100
    _, values = _replayed(recording, "arm")
    assert max(v for v in plot.values[0] if v is not None) == pytest.approx(values[0].max())
    assert min(v for v in plot.values[2] if v is not None) == pytest.approx(values[2].min())
    nan_row = channels.plot_data(recording, "f64", points=2000).values[0]
    assert nan_row[7] is None  # NaN goes out as null
    with pytest.raises(UnknownProviderError):
        channels.plot_data(recording, "nothing", points=100)
    with pytest.raises(InvalidSampleError):
        channels.plot_data(recording, "words", points=100)


def test_a_file_cut_short_is_scanned_and_reads_what_replay_reads(
    recording: Path, tmp_path: Path
) -> None:
    whole = mcap_file(recording).read_bytes()
    cut = tmp_path / "cut.mcap"
    cut.write_bytes(whole[: len(whole) * 2 // 3])  # as a crash leaves it: no summary
    assert not McapFile.open(cut).indexed
    replayer = Replayer(cut)
    assert not replayer.complete and 0 < replayer.frame_count < 400
    scan = scan_channel(cut, "arm")
    assert scan.values is not None and scan.time_ns is not None
    series = channels._read_series(replayer, "arm", replayer.providers["arm"])
    np.testing.assert_array_equal(scan.time_ns, series.time_ns)
    np.testing.assert_array_equal(scan.values.T, series.values)


def test_the_channel_list_from_the_indexes_is_the_one_replay_gives(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    path = tmp_path / "ep"
    recorder = Recorder(path, episode_id="ep", flush_interval_s=0.01)
    recorder.add_provider("f64", "float_array", dtype="float64", shape=[2])
    recorder.add_provider("arm", "joint_state", names=["a"])
    recorder.add_provider("words", "string")
    recorder.add_provider("silent", "float_array", dtype="float64", shape=[1])
    for i in range(250):
        samples: dict[str, object] = {"f64": [i, -i]}
        if i % 3 == 0:
            samples["arm"] = [0.5]
        if i in (10, 200):
            samples["words"] = f"at {i}"
        recorder.tick(samples, time_ns=T0 + i * 7_000_000)
    recorder.close()
    assert scan_channel(mcap_file(path), "silent").values is not None

    channels._cache.clear()
    indexed = channels.channel_list("ep", path)
    channels._cache.clear()
    monkeypatch.setattr(series, "recording_times", lambda _file, **_: None)
    replayed = channels.channel_list("ep", path)
    assert indexed.model_dump() == replayed.model_dump()
    counts = {c.name: c.samples for c in indexed.channels}
    assert counts == {"f64": 250, "arm": 84, "words": 2, "silent": 0}
    assert indexed.frames == 250 and indexed.start_ns == T0


def test_a_baseline_filtered_recording_lists_its_channels_by_replay(recording: Path) -> None:
    from api.views.series import recording_times

    assert recording_times(mcap_file(recording)) is None
    listed = {c.name: c.samples for c in channels.channel_list("ep", recording).channels}
    assert listed["still"] == 400 and listed["f32"] == 134
