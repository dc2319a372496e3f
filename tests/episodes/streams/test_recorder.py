"""Recording: typed channels, ticks, baseline filter, rate limit, drop accounting, bad input."""

import threading
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from rosbags.rosbag2 import Reader

from episodes.streams import (
    InvalidSampleError,
    Recorder,
    RecordingStateError,
    Replayer,
    UnknownProviderError,
)

Recorded = tuple[Path, list[dict[str, Any]], list[int]]


def test_every_channel_replays_bit_exact(recorded: Recorded, same: Callable[..., None]) -> None:
    path, sent, times = recorded
    frames = list(Replayer(path).frames())
    assert [f.number for f in frames] == list(range(1, 31))
    assert [f.time_ns for f in frames] == times
    for frame, samples in zip(frames, sent, strict=True):
        assert set(frame.samples) == set(samples)
        for name, value in samples.items():
            same(name, frame.samples[name].value, value)


def test_samples_of_a_tick_share_time_and_frame_next_to_sensor_stamps(tmp_path: Path) -> None:
    rec = Recorder(tmp_path / "ep", episode_id="ep")
    rec.add_provider("a", "string")
    rec.add_provider("b", "string")
    result = rec.tick({"a": "x", "b": "y"}, time_ns=5_000, stamps_ns={"a": 4_100, "b": 4_900})
    rec.tick({"b": "z"}, time_ns=6_000)
    rec.close()
    frames = list(Replayer(tmp_path / "ep").frames())
    first = frames[0].samples
    assert result.frame == 1 and result.queued == ("a", "b")
    assert (first["a"].time_ns, first["a"].frame, first["a"].stamp_ns) == (5_000, 1, 4_100)
    assert (first["b"].time_ns, first["b"].frame, first["b"].stamp_ns) == (5_000, 1, 4_900)
    assert (frames[1].number, frames[1].samples["b"].stamp_ns) == (2, 6_000)


def test_baseline_samples_take_no_space_and_come_back(recorded: Recorded) -> None:
    path, sent, _ = recorded
    touched = sum(1 for s in sent if (s["icub/skin/torso"] != 5.0).any())
    reader = Reader(path)
    reader.open()
    counts = {c.topic: c.msgcount for c in reader.connections}
    reader.close()
    # the file holds only the touched samples, sparse; the others are restored on read
    assert counts["/icub/skin/torso"] == touched < len(sent)
    replayed = [f.samples["icub/skin/torso"] for f in Replayer(path).frames()]
    assert sum(s.from_baseline for s in replayed) == len(sent) - touched
    assert all(
        np.array_equal(s.value, v["icub/skin/torso"]) for s, v in zip(replayed, sent, strict=True)
    )


def test_stats_count_what_was_stored(tmp_path: Path) -> None:
    rec = Recorder(tmp_path / "ep", episode_id="ep")
    rec.add_provider("skin", "float_array", baseline=np.zeros(4))
    rec.tick({"skin": np.zeros(4)}, time_ns=10)
    rec.tick({"skin": [0.0, 1.0, 0.0, 0.0]}, time_ns=20)
    (stats,) = rec.close()
    assert (stats.provider, stats.channel, stats.message_type) == (
        "skin",
        "/skin",
        "engram_msgs/msg/SparseArray",
    )
    assert (stats.count_received, stats.count_stored, stats.baseline_samples) == (2, 2, 1)
    assert (stats.first_time_ns, stats.last_time_ns, stats.dropped) == (10, 20, {})
    assert stats.path == tmp_path / "ep" / "ep.mcap" and stats.path.is_file()
    assert stats.as_dict()["first_time"] == "1970-01-01T00:00:00.000000Z"


def test_rate_limit_keeps_one_sample_per_period(tmp_path: Path) -> None:
    rec = Recorder(tmp_path / "ep", episode_id="ep")
    rec.add_provider("joints", "joint_state", names=["j"], rate_limit_hz=25)
    rec.add_provider("free", "string")
    period = 10_000_000  # 100 Hz source, limited to 25 Hz
    for i in range(100):
        rec.tick({"joints": [float(i)], "free": str(i)}, time_ns=(i + 1) * period)
    stats = {s.provider: s for s in rec.close()}
    assert stats["joints"].count_stored == 25
    assert stats["joints"].dropped == {"rate_limit": 75}
    assert stats["free"].count_stored == 100
    kept = [
        f.samples["joints"].value["position"][0]
        for f in Replayer(tmp_path / "ep").frames()
        if "joints" in f.samples
    ]
    assert kept == [float(i) for i in range(0, 100, 4)]


def test_a_full_queue_drops_and_counts_never_blocks(tmp_path: Path) -> None:
    rec = Recorder(tmp_path / "ep", episode_id="ep", max_queue_bytes=20_000)
    rec.add_provider("blob", "float_array", dtype="float64")
    writer = rec.writer.bag
    write = writer.write
    disk_free = threading.Event()

    def slow_disk(*args: Any) -> None:  # the disk stalls until the test frees it
        disk_free.wait(10)
        write(*args)

    writer.write = slow_disk  # type: ignore[method-assign]
    results = [rec.tick({"blob": np.full(1000, float(i))}) for i in range(5)]
    disk_free.set()
    (stats,) = rec.close()
    kept = [r.frame for r in results if r.frame is not None]
    assert kept == [1, 2]  # 8 kB each: two fit in 20 kB
    assert [r.dropped for r in results[2:]] == [{"blob": "queue_full"}] * 3
    assert (stats.count_received, stats.count_stored, stats.dropped) == (5, 2, {"queue_full": 3})
    assert [f.samples["blob"].value[0] for f in Replayer(tmp_path / "ep").frames()] == [0.0, 1.0]


def test_providers_can_join_while_recording(tmp_path: Path) -> None:
    rec = Recorder(tmp_path / "ep", episode_id="ep")
    rec.add_provider("a", "string")
    rec.tick({"a": "1"})
    rec.add_provider("late", "float_array", dtype="float32")
    rec.tick({"a": "2", "late": [1.5]})
    rec.remove_provider("a")
    with pytest.raises(UnknownProviderError):
        rec.tick({"a": "3"})
    rec.close()
    frames = list(Replayer(tmp_path / "ep").frames())
    assert [sorted(f.samples) for f in frames] == [["a"], ["a", "late"]]


BAD_TICKS: list[tuple[dict[str, Any], dict[str, Any], type[Exception], str]] = [
    ({"nope": "x"}, {}, UnknownProviderError, "'nope' is not registered"),
    ({"head": [1.0]}, {}, InvalidSampleError, "samples[head].position: got [1]"),
    ({"head": "abc"}, {}, InvalidSampleError, "samples[head]"),
    ({"head": {"angle": [1, 2]}}, {}, InvalidSampleError, "position, velocity, effort"),
    ({"f32": np.zeros(3)}, {}, InvalidSampleError, "got 'array of float64', expected a float32"),
    ({"cam": np.zeros((4, 4), np.uint8)}, {}, InvalidSampleError, "(height, width, 3)"),
    ({"cam": np.zeros((4, 4, 3))}, {}, InvalidSampleError, "array of float64"),
    ({"text": 5}, {}, InvalidSampleError, "expected a string"),
    ({"text": "x"}, {"time_ns": 50}, InvalidSampleError, "after the previous one (100)"),
    ({"text": "x"}, {"time_ns": -3}, InvalidSampleError, "time_ns: got -3"),
    ({"text": "x"}, {"stamps_ns": {"text": 1.5}}, InvalidSampleError, "stamps_ns[text]"),
    ({"text": "x"}, {"stamps_ns": {"cam": 1}}, InvalidSampleError, "a provider that has"),
]


@pytest.mark.parametrize(("samples", "options", "error", "fragment"), BAD_TICKS)
def test_bad_ticks_are_refused_and_change_nothing(
    tmp_path: Path,
    samples: dict[str, Any],
    options: dict[str, Any],
    error: type[Exception],
    fragment: str,
) -> None:
    rec = Recorder(tmp_path / "ep", episode_id="ep")
    rec.add_provider("head", "joint_state", names=["a", "b"])
    rec.add_provider("f32", "float_array", dtype="float32")
    rec.add_provider("cam", "image")
    rec.add_provider("text", "string")
    rec.tick({"text": "first", "head": [1.0, 2.0]}, time_ns=100)
    with pytest.raises(error) as info:
        rec.tick({"text": "ok", **samples}, **options)
    assert fragment in str(info.value)
    assert rec.tick({"text": "next"}, time_ns=200).frame == 2
    stats = {s.provider: (s.count_received, s.count_stored) for s in rec.close()}
    assert stats == {"head": (1, 1), "f32": (0, 0), "cam": (0, 0), "text": (2, 2)}


BAD_PROVIDERS: list[tuple[str, str, dict[str, Any], str]] = [
    ("has space", "string", {}, "name: got 'has space'"),
    ("engram/ticks", "string", {}, "reserved"),
    ("x", "video", {}, "kind: got 'video'"),
    ("x", "float_array", {"dtype": "int8"}, "'float32' or 'float64'"),
    ("x", "joint_state", {}, "names: got None"),
    ("x", "image", {"encoding": "yuv"}, "encoding: got 'yuv'"),
    ("x", "audio", {"sample_rate": 0}, "sample_rate: got 0"),
    ("x", "string", {"rate_limit_hz": 0}, "rate_limit_hz: got 0"),
    ("x", "string", {"baseline": 1.0}, "no baseline except for float_array"),
    ("x", "float_array", {"baseline": 1.0}, "shape: got None"),
    ("x", "float_array", {"baseline": [1.0, 2.0], "shape": [3]}, "baseline: got (2,)"),
]


@pytest.mark.parametrize(("name", "kind", "settings", "fragment"), BAD_PROVIDERS)
def test_bad_provider_settings_are_refused(
    tmp_path: Path, name: str, kind: str, settings: dict[str, Any], fragment: str
) -> None:
    rec = Recorder(tmp_path / "ep", episode_id="ep")
    with pytest.raises(InvalidSampleError, match=None) as info:
        rec.add_provider(name, kind, **settings)
    assert fragment in str(info.value)
    assert rec.providers == {}
    rec.close()


def test_closed_recordings_refuse_samples_and_paths_are_never_reused(tmp_path: Path) -> None:
    rec = Recorder(tmp_path / "ep", episode_id="ep")
    rec.add_provider("a", "string")
    rec.close()
    with pytest.raises(RecordingStateError, match="closed"):
        rec.tick({"a": "late"})
    with pytest.raises(RecordingStateError, match="exists already"):
        Recorder(tmp_path / "ep", episode_id="ep")


def test_producers_in_several_threads_get_distinct_frames(tmp_path: Path) -> None:
    rec = Recorder(tmp_path / "ep", episode_id="ep")
    for k in range(4):
        rec.add_provider(f"p{k}", "float_array", dtype="float64")

    def produce(k: int) -> None:
        for i in range(200):
            rec.tick({f"p{k}": [float(i)]})

    threads = [threading.Thread(target=produce, args=(k,)) for k in range(4)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    stats = rec.close()
    assert all(s.count_stored == 200 for s in stats)
    frames = list(Replayer(tmp_path / "ep").frames())
    assert [f.number for f in frames] == list(range(1, 801))
    for k in range(4):
        values = [f.samples[f"p{k}"].value[0] for f in frames if f"p{k}" in f.samples]
        assert values == [float(i) for i in range(200)]


def test_a_recording_without_ticks_is_still_a_valid_bag(tmp_path: Path) -> None:
    rec = Recorder(tmp_path / "ep", episode_id="ep", clock=lambda: 42_000)
    rec.add_provider("a", "string")
    rec.flush()
    assert rec.close()[0].count_stored == 0
    replayer = Replayer(tmp_path / "ep")
    assert (replayer.frame_count, list(replayer.providers), replayer.complete) == (0, ["a"], True)
    reader = Reader(tmp_path / "ep")
    reader.open()
    assert reader.start_time == 42_000
    reader.close()


def test_zstd_chunks_replay_bit_exact(
    tmp_path: Path,
    new_recorder: Callable[..., Recorder],
    samples_for: Callable[..., dict[str, Any]],
    same: Callable[..., None],
) -> None:
    rng = np.random.default_rng(11)
    rec = new_recorder(tmp_path / "ep-z", compression="zstd", flush_interval_s=0.01)
    sent = [samples_for(rng, i) for i in range(12)]
    for samples in sent:
        rec.tick(samples)
    rec.close()
    assert b"zstd" in (tmp_path / "ep-z" / "ep-z.mcap").read_bytes()  # chunk compression
    for frame, samples in zip(Replayer(tmp_path / "ep-z").frames(), sent, strict=True):
        for name, value in samples.items():
            same(name, frame.samples[name].value, value)
