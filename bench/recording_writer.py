"""The recorder's writer thread on large samples: CPU time per 640x480 RGB frame (serialising
and writing it through ``episodes.streams.bagwrite``), measured by the thread's own clock
(``Recorder.writer.cpu_s``), so the machine's load does not enter the figure.

With ``--against <checkout>`` the same recording is also made by another checkout's recorder
(e.g. the main branch before a change), each run in a fresh process, the two alternating, and
the ratio printed; the load average is printed beside the figures.

    PYTHONPATH=. .venv/bin/python bench/recording_writer.py [--frames 300] [--against ../main]
"""

import argparse
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np


def child(frames: int, compression: str | None) -> None:
    """Record ``frames`` random frames with the importable ``episodes``; print ms per frame."""
    from episodes.streams import Recorder

    image = np.random.default_rng(0).integers(0, 256, (480, 640, 3), dtype=np.uint8)
    root = Path(tempfile.mkdtemp(prefix="engram-writer-"))
    try:
        recorder = Recorder(
            root / "ep", episode_id="ep", max_queue_bytes=2**31, compression=compression
        )
        recorder.add_provider("cam", "image", encoding="rgb8")
        for k in range(frames):
            recorder.tick({"cam": image}, time_ns=1_000_000_000 + k)
        stats = recorder.close()
        assert stats[0].count_stored == frames, stats
        writer = getattr(recorder, "writer", None)  # a checkout before the recorder's split
        cpu_s = writer.cpu_s if writer is not None else recorder.writer_cpu_s
        print(cpu_s / frames * 1e3)
    finally:
        shutil.rmtree(root, ignore_errors=True)


def run(checkout: Path, frames: int, compression: str | None) -> float:
    """CPU ms per frame of ``checkout``'s recorder writer thread, in a fresh process."""
    args = [sys.executable, __file__, "--child", "--frames", str(frames)]
    if compression:
        args += ["--compression", compression]
    env = dict(os.environ, PYTHONPATH=str(checkout))
    out = subprocess.run(args, env=env, check=True, capture_output=True, text=True, cwd="/")
    return float(out.stdout.strip().splitlines()[-1])


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--frames", type=int, default=300)
    parser.add_argument("--rounds", type=int, default=5)
    parser.add_argument("--compression", choices=["zstd", "lz4"], default=None)
    parser.add_argument("--against", type=Path, help="another checkout, measured alike")
    parser.add_argument("--child", action="store_true", help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.child:
        child(args.frames, args.compression)
        return
    here = Path(__file__).resolve().parent.parent
    ours: list[float] = []
    theirs: list[float] = []
    for _ in range(args.rounds):  # alternating, so both see the same machine
        ours.append(run(here, args.frames, args.compression))
        if args.against is not None:
            theirs.append(run(args.against.resolve(), args.frames, args.compression))
    label = f"{args.frames} frames of 640x480 rgb8, {args.compression or 'uncompressed'}"
    print(f"{label}, median of {args.rounds} runs, writer-thread CPU per frame")
    print(f"{here}: {statistics.median(ours):.3f} ms  (runs: {_list(ours)})")
    if theirs:
        print(f"{args.against}: {statistics.median(theirs):.3f} ms  (runs: {_list(theirs)})")
        print(f"ratio: {statistics.median(ours) / statistics.median(theirs):.2f}")
    with open("/proc/loadavg") as load:
        print(f"load average: {load.read().strip()}")


def _list(values: list[float]) -> str:
    return ", ".join(f"{v:.3f}" for v in values)


if __name__ == "__main__":
    main()
