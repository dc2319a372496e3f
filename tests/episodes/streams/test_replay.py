"""Replay: frame by frame vs real time (injectable clock), speed, seek, channel subsets."""

from pathlib import Path
from typing import Any

import numpy as np
import pytest

from episodes.streams import InvalidSampleError, Recorder, Replayer, UnknownProviderError

MS = 1_000_000
T0 = 1_700_000_000_000_000_000


class FakeClock:
    """Seconds that pass only when the replayer sleeps or the test says so."""

    def __init__(self) -> None:
        self.now = 100.0
        self.sleeps: list[float] = []

    def __call__(self) -> float:
        return self.now

    def sleep(self, seconds: float) -> None:
        self.sleeps.append(seconds)
        self.now += seconds


@pytest.fixture
def ten_frames(tmp_path: Path) -> Path:
    """Frames 1..10 every 10 ms: 'joints' in every frame, 'cam' in odd frames only."""
    rec = Recorder(tmp_path / "ep-7", episode_id="ep-7")
    rec.add_provider("joints", "float_array", dtype="float64")
    rec.add_provider("cam", "image", encoding="mono8")
    for i in range(10):
        samples: dict[str, Any] = {"joints": [float(i)]}
        if i % 2 == 0:
            samples["cam"] = np.full((2, 2), i, dtype=np.uint8)
        rec.tick(samples, time_ns=T0 + i * 10 * MS)
    rec.close()
    return tmp_path / "ep-7"


def test_frame_by_frame_sends_everything_with_provenance(ten_frames: Path) -> None:
    frames = list(Replayer(ten_frames).frames())
    assert [f.number for f in frames] == list(range(1, 11))
    sample = frames[2].samples["cam"]
    assert (sample.episode, sample.provider, sample.channel) == ("ep-7", "cam", "/cam")
    assert (sample.frame, sample.time_ns, sample.stamp_ns) == (3, T0 + 20 * MS, T0 + 20 * MS)


def test_real_time_waits_for_each_frame_when_the_consumer_keeps_up(ten_frames: Path) -> None:
    clock = FakeClock()
    replayer = Replayer(ten_frames, clock=clock, sleep=clock.sleep)
    frames = list(replayer.play())
    assert [f.number for f in frames] == list(range(1, 11))
    assert clock.sleeps == pytest.approx([0.01] * 9)
    assert replayer.skipped == 0


def test_real_time_skips_late_frames_and_sends_the_newest_due(ten_frames: Path) -> None:
    clock = FakeClock()
    replayer = Replayer(ten_frames, clock=clock, sleep=clock.sleep)
    got = []
    for frame in replayer.play():
        got.append((frame.number, {k: s.frame for k, s in frame.samples.items()}))
        clock.now += 0.036  # the consumer needs 36 ms per frame: 3.6 frames of 10 ms
    # after frame 1, frames 2-4 are due at once: only the newest of each channel is sent
    assert got[0] == (1, {"joints": 1, "cam": 1})
    assert got[1] == (4, {"joints": 4, "cam": 3})
    assert [n for n, _ in got] == [1, 4, 8, 10]
    assert replayer.skipped == 7  # joints 2, 3, 5, 6, 7, 9 and cam 5
    assert got[2] == (8, {"joints": 8, "cam": 7})


def test_speed_factor_scales_the_waits(ten_frames: Path) -> None:
    clock = FakeClock()
    frames = list(Replayer(ten_frames, clock=clock, sleep=clock.sleep).play(speed=0.5))
    assert len(frames) == 10
    assert clock.sleeps == pytest.approx([0.02] * 9)


def test_seek_by_time_or_frame_and_a_subset_of_channels(ten_frames: Path) -> None:
    replayer = Replayer(ten_frames)
    assert replayer.seek(time_ns=T0 + 45 * MS) == 5
    assert [f.number for f in replayer.frames(["cam"])] == [7, 9]
    replayer.seek(frame=9)
    assert [sorted(f.samples) for f in replayer.frames()] == [["cam", "joints"], ["joints"]]
    replayer.seek(frame=1)
    assert [f.number for f in replayer.frames(["/joints"], end_ns=T0 + 20 * MS)] == [1, 2, 3]


def test_bad_replay_arguments_name_the_field(ten_frames: Path) -> None:
    replayer = Replayer(ten_frames)
    with pytest.raises(UnknownProviderError, match="'mic' is not a channel"):
        list(replayer.frames(["mic"]))
    with pytest.raises(InvalidSampleError, match="speed: got 0"):
        list(replayer.play(speed=0))
    with pytest.raises(InvalidSampleError, match="exactly one"):
        replayer.seek()
