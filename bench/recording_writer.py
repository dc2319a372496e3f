"""The recorder's writer on large samples: one 640x480 RGB frame written through rosbags'
MCAP writer (``Writer.write``) against ``episodes.streams.mcap_direct.write_alone`` (a chunk of
its own, written once), in the same process on the same serialised frames; ms per frame,
the ratio, and the load average.

    .venv/bin/python bench/recording_writer.py [--frames 300]
"""

import argparse
import shutil
import statistics
import tempfile
import time
from pathlib import Path

import numpy as np
from rosbags.rosbag2 import StoragePlugin, Writer

from episodes.streams import messages
from episodes.streams.mcap_direct import write_alone


def per_frame(direct: bool, data: memoryview, frames: int, root: Path) -> float:
    """Seconds per frame written, file flushed and closed included."""
    path = root / ("direct" if direct else "rosbags")
    writer = Writer(path, version=9, storage_plugin=StoragePlugin.MCAP)
    writer.open()
    connection = writer.add_connection(
        "/cam", "sensor_msgs/msg/Image", typestore=messages.typestore()
    )
    start = time.perf_counter()
    for k in range(frames):
        if direct:
            write_alone(writer, connection, 1 + k, data)
        else:
            writer.write(connection, 1 + k, data)
    writer.close()
    seconds = (time.perf_counter() - start) / frames
    shutil.rmtree(path)
    return seconds


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--frames", type=int, default=300)
    parser.add_argument("--rounds", type=int, default=5)
    args = parser.parse_args()
    image = np.random.default_rng(0).integers(0, 256, (480, 640, 3), dtype=np.uint8)
    spec = messages.ProviderSpec.create("cam", "image", encoding="rgb8")
    data = messages.typestore().serialize_cdr(
        messages.encode(spec, 1, messages.check(spec, image)), spec.msgtype
    )
    root = Path(tempfile.mkdtemp(prefix="engram-writer-"))
    try:
        rosbags_s, direct_s = [], []
        for _ in range(args.rounds):  # interleaved, so both see the same machine load
            rosbags_s.append(per_frame(False, data, args.frames, root))
            direct_s.append(per_frame(True, data, args.frames, root))
    finally:
        shutil.rmtree(root, ignore_errors=True)
    before, after = statistics.median(rosbags_s), statistics.median(direct_s)
    print(f"{len(data) / 1e6:.2f} MB per frame, {args.frames} frames x {args.rounds} rounds")
    print(f"rosbags Writer.write      {before * 1e3:7.3f} ms/frame")
    print(f"mcap_direct.write_alone   {after * 1e3:7.3f} ms/frame   ({before / after:.1f}x faster)")
    with open("/proc/loadavg") as load:
        print(f"load average: {load.read().strip()}")


if __name__ == "__main__":
    main()
