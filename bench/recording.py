"""The stream recorder under the sensor load of the paper's Table I (iCub, NAO, Baxter).

Table I of Petit, Fischer & Demiris (IEEE TCDS 2016), "stored data ... including the sensor
frequency":

=======  =====================================  ===========  =========
robot    data                                   per frame    Hz
=======  =====================================  ===========  =========
iCub     RGB Kinect, 640x480                    1            30
iCub     joints (double)                        53           100
iCub     RGB cameras (high res), 640x480        2            15
iCub     RGB cameras (low res), 320x240         2            25
iCub     skin (double)                          4224         50
NAO      joints (double)                        25           50
NAO      RGB camera, 320x240                    1            15
Baxter   joints (double)                        16           100
Baxter   RGB head camera, 640x400               1            25
=======  =====================================  ===========  =========

Each robot gets one producer thread that runs a 5 ms loop like the original's (every sensor
whose next sample is due joins that loop's tick) and feeds a :class:`Recorder` in real time
for ``--seconds``. Images are random (incompressible) frames, joints are sine waves, the skin
sits at its baseline (5.0) except while touched (a patch of 60 taxels in a quarter of the
samples). Printed per provider: samples expected (rate x duration), received, share stored
(target 100 %), dropped (target 0), bytes written and the writer thread's time on that
provider (its share of one core). Per robot: CPU of the whole process (producer + writer), the
file size and write rate. Then ``--capacity-seconds`` runs with 1, 2, 3, ... iCubs recorded
at once in this one process, up to the first count that drops a sample or whose producers fall
more than 100 ms behind their sensors.

Run from the repository root::

    .venv/bin/python bench/recording.py                       # 60 s per robot
    .venv/bin/python bench/recording.py --seconds 10 --capacity-seconds 5
"""

from __future__ import annotations

import argparse
import math
import os
import platform
import shutil
import tempfile
import threading
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from episodes.streams import ChannelStats, Recorder

LOOP_S = 0.005
SKIN_BASELINE = 5.0


@dataclass(frozen=True)
class Sensor:
    name: str
    kind: str
    hz: float
    settings: dict[str, Any] = field(default_factory=dict)
    shape: tuple[int, ...] = ()


def _camera(name: str, hz: float, height: int, width: int) -> Sensor:
    return Sensor(name, "image", hz, {"encoding": "rgb8"}, (height, width, 3))


def _joints(name: str, hz: float, n: int) -> Sensor:
    return Sensor(name, "joint_state", hz, {"names": [f"j{i}" for i in range(n)]}, (n,))


ROBOTS: dict[str, list[Sensor]] = {
    "icub": [
        _camera("kinect/rgb", 30, 480, 640),
        _joints("icub/joints", 100, 53),
        _camera("icub/cam/left", 15, 480, 640),
        _camera("icub/cam/right", 15, 480, 640),
        _camera("icub/cam_low/left", 25, 240, 320),
        _camera("icub/cam_low/right", 25, 240, 320),
        Sensor(
            "icub/skin",
            "float_array",
            50,
            {"dtype": "float64", "shape": [4224], "baseline": SKIN_BASELINE},
            (4224,),
        ),
    ],
    "nao": [_joints("nao/joints", 50, 25), _camera("nao/camera", 15, 240, 320)],
    "baxter": [_joints("baxter/joints", 100, 16), _camera("baxter/head_camera", 25, 400, 640)],
}


class Source:
    """Synthetic samples of one sensor, cheap to produce (pre-made frames are cycled)."""

    def __init__(self, sensor: Sensor, rng: np.random.Generator) -> None:
        self.sensor = sensor
        self.i = 0
        if sensor.kind == "image":
            self.frames = [rng.integers(0, 256, sensor.shape, dtype=np.uint8) for _ in range(4)]
        elif sensor.kind == "float_array":
            self.touched = []
            for k in range(8):
                skin = np.full(sensor.shape, SKIN_BASELINE)
                start = (k * 523) % (sensor.shape[0] - 60)
                skin[start : start + 60] = rng.uniform(6.0, 250.0, 60)
                self.touched.append(skin)
            self.rest = np.full(sensor.shape, SKIN_BASELINE)
        self.phase = (
            np.linspace(0, math.pi, sensor.shape[0]) if sensor.kind == "joint_state" else None
        )

    def next(self) -> Any:
        self.i += 1
        if self.sensor.kind == "image":
            return self.frames[self.i % len(self.frames)]
        if self.sensor.kind == "float_array":
            return self.touched[self.i % 8] if self.i % 4 == 0 else self.rest
        assert self.phase is not None
        return np.sin(self.phase + self.i * 0.01)


@dataclass
class Run:
    robot: str
    seconds: float
    stats: list[ChannelStats]
    file_bytes: int
    producer_cpu_s: float
    writer_cpu_s: float
    max_lag_s: float


def record(robot: str, root: Path, seconds: float, tag: str, seed: int) -> Run:
    """Feed one robot's sensors into a recorder in real time; runs in the calling thread."""
    sensors = ROBOTS[robot]
    rng = np.random.default_rng(seed)
    rec = Recorder(root / f"{robot}-{tag}", episode_id=f"{robot}-{tag}")
    for sensor in sensors:
        rec.add_provider(sensor.name, sensor.kind, **sensor.settings)
    sources = [Source(s, rng) for s in sensors]
    total = [math.ceil(seconds * s.hz - 1e-9) for s in sensors]
    sent = [0] * len(sensors)
    cpu0 = time.thread_time()
    start = time.monotonic()
    wall0 = time.time_ns()
    max_lag = 0.0
    while True:
        now = time.monotonic()
        samples: dict[str, Any] = {}
        stamps: dict[str, int] = {}
        for k, source in enumerate(sources):
            due = start + sent[k] / source.sensor.hz
            if sent[k] < total[k] and due <= now:
                samples[source.sensor.name] = source.next()
                stamps[source.sensor.name] = wall0 + int((due - start) * 1e9)
                max_lag = max(max_lag, now - due)
                sent[k] += 1
        if samples:
            rec.tick(samples, stamps_ns=stamps)
        pending = [start + sent[k] / s.hz for k, s in enumerate(sensors) if sent[k] < total[k]]
        if not pending:
            break
        wait = min(min(pending) - time.monotonic(), LOOP_S)
        if wait > 0:
            time.sleep(wait)
    producer_cpu = time.thread_time() - cpu0
    stats = rec.close()
    size = sum(f.stat().st_size for f in rec.path.iterdir())
    return Run(robot, seconds, stats, size, producer_cpu, rec.writer.cpu_s, max_lag)


def _expected(robot: str, seconds: float) -> dict[str, int]:
    return {s.name: math.ceil(seconds * s.hz - 1e-9) for s in ROBOTS[robot]}


def report(run: Run) -> None:
    expected = _expected(run.robot, run.seconds)
    hz = {s.name: s.hz for s in ROBOTS[run.robot]}
    print(f"\n{run.robot}: {run.seconds:g} s")
    head = (
        f"{'provider':22} {'Hz':>5} {'expected':>8} {'received':>8} {'stored':>8} "
        f"{'stored %':>8} {'dropped':>7} {'baseline':>8} {'MB written':>10} {'writer time %':>13}"
    )
    print(head)
    print("-" * len(head))
    for s in run.stats:
        share = 100.0 * s.count_stored / expected[s.provider]
        print(
            f"{s.provider:22} {hz[s.provider]:>5g} {expected[s.provider]:>8} "
            f"{s.count_received:>8} {s.count_stored:>8} {share:>7.1f}% {s.count_dropped:>7} "
            f"{s.baseline_samples:>8} {s.bytes_written / 1e6:>10.1f} "
            f"{100 * s.write_seconds / run.seconds:>12.1f}%"
        )
    cpu = run.producer_cpu_s + run.writer_cpu_s
    print(
        f"process CPU: {100 * cpu / run.seconds:.1f} % of one core "
        f"(producer {100 * run.producer_cpu_s / run.seconds:.1f} %, "
        f"writer {100 * run.writer_cpu_s / run.seconds:.1f} %); "
        f"file {run.file_bytes / 1e6:.0f} MB, {run.file_bytes / 1e6 / run.seconds:.1f} MB/s; "
        f"producer late by at most {1000 * run.max_lag_s:.1f} ms"
    )


MAX_LAG_S = 0.1  # a producer later than this has fallen behind its sensors


def ok(run: Run) -> bool:
    """Every sample stored, none dropped, and the producer kept up with real time."""
    expected = _expected(run.robot, run.seconds)
    return run.max_lag_s < MAX_LAG_S and all(
        s.count_dropped == 0 and s.count_stored >= expected[s.provider] for s in run.stats
    )


def capacity(root: Path, seconds: float, max_robots: int, counts: list[int] | None = None) -> None:
    print(f"\ncapacity: n iCubs recorded at once in one process, {seconds:g} s each run")
    print(
        f"{'n':>3} {'all stored':>10} {'dropped':>7} {'worst stored %':>14} "
        f"{'process CPU %':>13} {'MB/s':>7} {'max lag ms':>10}"
    )
    best = 0
    for n in counts or range(1, max_robots + 1):
        runs: list[Run] = []
        lock = threading.Lock()

        def one(k: int, runs: list[Run] = runs, lock: threading.Lock = lock) -> None:
            run = record("icub", root, seconds, f"cap{k}", seed=k)
            with lock:
                runs.append(run)

        cpu0 = time.process_time()
        wall0 = time.monotonic()
        threads = [threading.Thread(target=one, args=(k,)) for k in range(n)]
        for t in threads:
            t.start()
        for t in threads:
            t.join()
        wall = time.monotonic() - wall0
        cpu = time.process_time() - cpu0
        worst = min(
            100.0 * s.count_stored / _expected("icub", seconds)[s.provider]
            for r in runs
            for s in r.stats
        )
        dropped = sum(s.count_dropped for r in runs for s in r.stats)
        good = all(ok(r) for r in runs)
        size = sum(r.file_bytes for r in runs)
        print(
            f"{n:>3} {'yes' if good else 'no':>10} {dropped:>7} {worst:>13.1f}% "
            f"{100 * cpu / wall:>12.0f}% {size / 1e6 / wall:>7.0f} "
            f"{1000 * max(r.max_lag_s for r in runs):>10.1f}"
        )
        for k in range(n):
            shutil.rmtree(root / f"icub-cap{k}", ignore_errors=True)
        if not good:
            if counts:
                continue
            break
        best = n
    print(
        f"one process records {best} iCub(s) at once with every sample stored, none dropped "
        f"and no producer more than {1000 * MAX_LAG_S:.0f} ms late"
    )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--seconds", type=float, default=60.0, help="duration per robot")
    parser.add_argument("--robots", nargs="+", default=list(ROBOTS), choices=list(ROBOTS))
    parser.add_argument(
        "--capacity-seconds",
        type=float,
        default=10.0,
        help="duration of each capacity run (0: skip)",
    )
    parser.add_argument("--max-robots", type=int, default=6)
    parser.add_argument(
        "--counts",
        type=int,
        nargs="+",
        default=None,
        help="run exactly these numbers of iCubs (default: 1, 2, ... up to the first failure)",
    )
    parser.add_argument("--dir", type=Path, default=None, help="where to write (default: tmp)")
    args = parser.parse_args()

    root = Path(tempfile.mkdtemp(prefix="engram-bench-", dir=args.dir))
    print(f"python {platform.python_version()}, {os.cpu_count()} cores, writing to {root}")
    try:
        for robot in args.robots:
            run = record(robot, root, args.seconds, "solo", seed=1)
            report(run)
            shutil.rmtree(root / f"{robot}-solo", ignore_errors=True)
        if args.capacity_seconds > 0:
            capacity(root, args.capacity_seconds, args.max_robots, args.counts)
        with open("/proc/loadavg") as load:
            print(f"load average: {load.read().strip()}")
    finally:
        shutil.rmtree(root, ignore_errors=True)


if __name__ == "__main__":
    main()
