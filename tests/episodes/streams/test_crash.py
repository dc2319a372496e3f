"""A recording process killed with SIGKILL leaves a file readable up to the last flushed chunk."""

import os
import signal
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import numpy as np
import pytest
from rosbags.highlevel import AnyReader

from episodes.streams import Replayer, recover

CHILD = textwrap.dedent(
    """
    import sys, time
    import numpy as np
    from episodes.streams import Recorder

    rec = Recorder(sys.argv[1], episode_id="crash", flush_interval_s=0.05)
    rec.add_provider("joints", "float_array", dtype="float64")
    rec.add_provider("skin", "float_array", dtype="float64", shape=[64], baseline=5.0)
    rec.add_provider("cam", "image", encoding="rgb8")
    i = 0
    while True:
        skin = np.full(64, 5.0)
        if i % 4 == 0:
            skin[i % 64] = 50.0 + i
        rng = np.random.default_rng(i)
        rec.tick(
            {"joints": np.arange(8) + i * 0.5, "skin": skin,
             "cam": rng.integers(0, 256, (120, 160, 3), dtype=np.uint8)},
            time_ns=1_000_000_000 + i * 1_000_000,
        )
        i += 1
        if i == 300:
            rec.flush()
            print("flushed", i, flush=True)
        time.sleep(0.001 if i < 300 else 0.002)
    """
)


def expected(i: int) -> dict[str, np.ndarray]:
    skin = np.full(64, 5.0)
    if i % 4 == 0:
        skin[i % 64] = 50.0 + i
    rng = np.random.default_rng(i)
    return {
        "joints": np.arange(8) + i * 0.5,
        "skin": skin,
        "cam": rng.integers(0, 256, (120, 160, 3), dtype=np.uint8),
    }


@pytest.mark.slow
def test_sigkill_leaves_a_readable_recording(tmp_path: Path) -> None:
    bag = tmp_path / "crash"
    child = subprocess.Popen(
        [sys.executable, "-c", CHILD, str(bag)],
        stdout=subprocess.PIPE,
        text=True,
        env={**os.environ, "PYTHONPATH": str(Path(__file__).parents[3])},
    )
    try:
        assert child.stdout is not None
        assert child.stdout.readline().split() == ["flushed", "300"]
        # let it write some more, then kill it in the middle of whatever it is doing
        time.sleep(0.3)
        child.send_signal(signal.SIGKILL)
    finally:
        child.wait(30)
        if child.stdout is not None:
            child.stdout.close()
    assert child.returncode == -signal.SIGKILL
    assert not (bag / "metadata.yaml").exists()  # the writer never closed the bag

    replayer = Replayer(bag)
    assert not replayer.complete
    frames = list(replayer.frames())
    assert len(frames) >= 300  # everything flushed before the kill, maybe more
    for frame in frames:
        want = expected(frame.number - 1)
        for name, value in want.items():
            got = frame.samples[name].value
            assert got.tobytes() == value.tobytes(), (frame.number, name)

    # recover() completes the bag in place: then rosbags reads it like any other
    assert recover(bag) == len(frames)
    with AnyReader([bag]) as reader:
        counts = {c.topic: c.msgcount for c in reader.connections}
    assert counts["/engram/ticks"] == len(frames) == counts["/cam"]
    again = list(Replayer(bag).frames())
    assert [f.number for f in again] == [f.number for f in frames]
    assert all(
        a.samples["skin"].value.tobytes() == b.samples["skin"].value.tobytes()
        for a, b in zip(again, frames, strict=True)
    )
