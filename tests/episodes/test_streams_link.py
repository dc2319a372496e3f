"""The graph side of recordings: descriptors when an episode ends, files removed with it, and
nothing left behind when a begin or a delete fails."""

from pathlib import Path

import numpy as np
import pytest

from episodes import EpisodeMemory, InvalidInputError, lifecycle
from kg import TransactionError

T0 = 1_769_441_400_000_000_000


def record(memory: EpisodeMemory, episode_id: str, ticks: int = 5) -> None:
    recorder = memory.streams.recordings.get(episode_id)
    recorder.add_provider("icub/skin", "float_array", dtype="float32", shape=[8], baseline=0.0)
    recorder.add_provider("icub/head", "joint_state", names=["a", "b"])
    for i in range(ticks):
        skin = np.zeros(8, dtype=np.float32)
        skin[i % 8] = 9.5
        recorder.tick({"icub/skin": skin, "icub/head": [0.1 * i, 0.2]}, time_ns=T0 + i * 10**7)


def test_ending_an_episode_closes_its_recording_and_describes_each_channel(
    disk_memory: EpisodeMemory,
) -> None:
    episode = disk_memory.begin("babbling", record=True, begin="2026-01-26T15:30:00+00:00")
    record(disk_memory, episode.id)
    ended = disk_memory.end(episode.id, end="2026-01-26T15:31:00+00:00")
    assert episode.id not in disk_memory.streams.recordings
    assert [(s.provider, s.channel, s.count, s.dropped) for s in ended.streams] == [
        ("icub/head", "/icub/head", 5, 0),
        ("icub/skin", "/icub/skin", 5, 0),
    ]
    head = ended.streams[0]
    assert head.message_type == "sensor_msgs/msg/JointState"
    assert head.first_time is not None and head.last_time is not None
    assert int(head.first_time.timestamp() * 1e9) == pytest.approx(T0, abs=1000)
    assert (disk_memory.data_dir / "streams" / head.file).is_file()  # type: ignore[operator]


def test_a_recording_closed_before_the_end_is_described_from_its_file(
    disk_memory: EpisodeMemory,
) -> None:
    episode = disk_memory.begin("babbling", record=True, begin="2026-01-26T15:30:00+00:00")
    record(disk_memory, episode.id, ticks=3)
    disk_memory.streams.recordings.close(episode.id)
    ended = disk_memory.end(episode.id, end="2026-01-26T15:31:00+00:00")
    assert [(s.provider, s.count, s.dropped) for s in ended.streams] == [
        ("icub/head", 3, None),  # the file does not say what was dropped: unknown, not zero
        ("icub/skin", 3, None),
    ]


def test_a_failed_begin_leaves_no_recording_behind(disk_memory: EpisodeMemory) -> None:
    with pytest.raises(InvalidInputError):
        disk_memory.begin("", record=True, episode_id="bad1")
    assert "bad1" not in disk_memory.streams.recordings
    assert not disk_memory.streams.path("bad1").exists()


def test_a_failed_delete_keeps_triples_and_files(
    disk_memory: EpisodeMemory, monkeypatch: pytest.MonkeyPatch
) -> None:
    episode = disk_memory.begin("babbling", record=True, begin="2026-01-26T15:30:00+00:00")
    record(disk_memory, episode.id)
    disk_memory.end(episode.id, end="2026-01-26T15:31:00+00:00")
    before = len(disk_memory.store)

    def broken(*args: object) -> None:
        raise TransactionError("disk full")

    monkeypatch.setattr(lifecycle, "delete_episode_triples", broken)
    with pytest.raises(TransactionError):
        disk_memory.delete(episode.id)
    assert len(disk_memory.store) == before
    assert disk_memory.streams.path(episode.id).is_dir()
    assert not any(
        p.name.startswith(".deleting") for p in Path(disk_memory.data_dir or ".").rglob("*")
    )
    monkeypatch.undo()
    disk_memory.delete(episode.id)
    assert not disk_memory.streams.path(episode.id).exists()


def test_deleting_a_recording_episode_stops_the_recording(disk_memory: EpisodeMemory) -> None:
    episode = disk_memory.begin("babbling", record=True)
    record(disk_memory, episode.id, ticks=2)
    disk_memory.delete(episode.id)
    assert episode.id not in disk_memory.streams.recordings
    assert not disk_memory.streams.path(episode.id).exists()
