"""Large samples written straight to the file, each in a chunk of its own
(``episodes.streams.mcap_direct``): the bag reads back the same with the recorder's replayer,
rosbags and the ``mcap`` package, with the summary counting every message."""

from pathlib import Path

import numpy as np
from mcap.reader import make_reader
from rosbags.highlevel import AnyReader

from episodes.streams import Recorder, Replayer
from episodes.streams.mcap_direct import DIRECT_BYTES
from episodes.streams.recorder import mcap_file

T0 = 1_700_000_000_000_000_000


def record(path: Path, frames: int) -> list[np.ndarray]:
    rng = np.random.default_rng(7)
    images = [rng.integers(0, 256, (240, 320, 3), dtype=np.uint8) for _ in range(frames)]
    assert images[0].nbytes >= DIRECT_BYTES  # written alone
    recorder = Recorder(path, episode_id="big")
    recorder.add_provider("cam", "image", encoding="rgb8")
    recorder.add_provider("joints", "joint_state", names=["a", "b"])
    for k, image in enumerate(images):
        samples = {"joints": [k * 0.1, -k * 0.1]}
        if k % 2 == 0:
            samples["cam"] = image  # images on every other tick, joints on all
        recorder.tick(samples, time_ns=T0 + k * 10_000_000)
        if k == 3:
            recorder.add_provider("late", "image", encoding="rgb8")  # defined mid-recording
            recorder.tick({"late": image}, time_ns=T0 + k * 10_000_000 + 1)
    stats = {s.provider: s for s in recorder.close()}
    assert stats["cam"].count_stored == (frames + 1) // 2 and stats["late"].count_stored == 1
    return images


def test_large_samples_read_back_everywhere(tmp_path: Path) -> None:
    frames = 9
    images = record(tmp_path / "big", frames)
    replayed = list(Replayer(tmp_path / "big").frames())
    cams = [f.samples["cam"].value for f in replayed if "cam" in f.samples]
    assert len(cams) == (frames + 1) // 2
    for k, value in enumerate(cams):
        assert np.array_equal(value, images[2 * k])
    assert [
        f.samples["joints"].value["position"][0] for f in replayed if "joints" in f.samples
    ] == [k * 0.1 for k in range(frames)]
    late = [f.samples["late"].value for f in replayed if "late" in f.samples]
    assert len(late) == 1 and np.array_equal(late[0], images[3])

    with AnyReader([tmp_path / "big"]) as reader:
        counts: dict[str, int] = {}
        for connection, _, raw in reader.messages():
            counts[connection.topic] = counts.get(connection.topic, 0) + 1
            if connection.topic == "/cam":
                message = reader.deserialize(raw, connection.msgtype)
                assert (message.height, message.width) == (240, 320)
    assert counts["/cam"] == (frames + 1) // 2 and counts["/joints"] == frames

    with open(mcap_file(tmp_path / "big"), "rb") as stream:
        reader = make_reader(stream)
        summary = reader.get_summary()
        assert summary is not None
        assert len(summary.chunk_indexes) > (frames + 1) // 2  # one chunk per image at least
        by_topic = {c.id: c.topic for c in summary.channels.values()}
        counted = {by_topic[cid]: n for cid, n in summary.statistics.channel_message_counts.items()}
        times = [m.log_time for _, _, m in reader.iter_messages(log_time_order=False)]
    assert counted["/cam"] == (frames + 1) // 2 and counted["/late"] == 1
    assert times == sorted(times)  # the file is in log-time order
