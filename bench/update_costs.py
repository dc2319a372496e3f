"""Where one scene update's time goes as the memory grows: recognition, re-scoring, the write.

For memories of ``--sizes`` learned classes (built as ``bench/scene_memory.py`` builds them, on
an on-disk store in a temporary directory, then flushed and given their first sleep pass), a
novel 10-object scene is learned ``--updates`` times and a known one reinforced as often; for
each kind the medians of:

- ``wall``, ``cpu``: the update's wall time and the process's CPU time (every thread);
- ``recog``: recognition (the index's bitsets, the best class, then ordering every recognised
  class, which a learn does alongside the write);
- ``rescore``: ``ScoreTable.refresh``, the exact re-derivation of the score terms of the
  touched class and of every ancestor (CPU of the calling thread, part of it alongside the
  write);
- ``write``: the store applying the transaction (Oxigraph), and ``quads`` its size (the
  wrapper that times it, ``scene_memory.WriteTimer``, adds about 1 µs per quad to wall and cpu);
- ``ancestors``: how many classes the scene is recognised as, what the two above grow with.

With ``--profile N``, the N functions of largest own time over the learns and the reinforces
(cProfile) follow the table.

Run from the repository root::

    .venv/bin/python bench/update_costs.py --sizes 10000,30000 --updates 30
    .venv/bin/python bench/update_costs.py --quick      # tiny sizes, to exercise the script
"""

import argparse
import cProfile
import gc
import io
import pstats
import random
import shutil
import statistics
import sys
import tempfile
import time
from collections.abc import Callable
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

from scene_memory import SEED, WriteTimer, build, random_scene

import reasoners.memory
from kg import Store
from reasoners.index import SignatureIndex
from reasoners.memory import SceneMemory
from reasoners.score_table import ScoreTable

COLUMNS = ("wall", "cpu", "recog", "rescore", "write", "quads", "ancestors")


class Meter:
    """CPU time of the calling thread spent in one function or method, summed until :meth:`take`."""

    def __init__(self, owner: object, name: str) -> None:
        self.total = 0.0
        original: Callable[..., object] = getattr(owner, name)

        def measured(*args: object, **kwargs: object) -> object:
            began = time.thread_time()
            try:
                return original(*args, **kwargs)
            finally:
                self.total += time.thread_time() - began

        setattr(owner, name, measured)
        self.owner, self.name, self.original = owner, name, original

    def take(self) -> float:
        value, self.total = self.total, 0.0
        return value

    def remove(self) -> None:
        setattr(self.owner, self.name, self.original)


def run(size: int, args: argparse.Namespace, rng: random.Random) -> dict[str, object]:
    workdir = Path(tempfile.mkdtemp(prefix="engram-bench-"))
    recog = [
        Meter(SignatureIndex, "recognised"),
        Meter(reasoners.memory, "best_recognition"),
        Meter(reasoners.memory, "ordered_recognitions"),
    ]
    rescore = Meter(ScoreTable, "refresh")
    try:
        build(workdir / "store", size, rng)
        store = Store(workdir / "store")
        memory = SceneMemory(store)
        store.flush()
        known = random_scene(rng, 10)
        memory.store_scene(known)
        memory.sleep()
        memory.transactions.settle_view()
        gc.collect()
        writes = WriteTimer(store)
        rows: dict[str, dict[str, list[float]]] = {}
        profiles: dict[str, str] = {}
        for kind in ("learn", "reinforce"):
            table: dict[str, list[float]] = {c: [] for c in COLUMNS}
            profile = cProfile.Profile() if args.profile else None
            for _ in range(args.updates):
                scene = random_scene(rng, 10) if kind == "learn" else known
                [meter.take() for meter in recog], rescore.take()
                first = len(writes.times)
                began, cpu = time.perf_counter(), time.process_time()
                if profile is not None:
                    profile.enable()
                result = memory.store_scene(scene)
                if profile is not None:
                    profile.disable()
                table["wall"].append(1000 * (time.perf_counter() - began))
                table["cpu"].append(1000 * (time.process_time() - cpu))
                table["recog"].append(1000 * sum(meter.take() for meter in recog))
                table["rescore"].append(1000 * rescore.take())
                table["write"].append(1000 * sum(writes.times[first:]))
                table["quads"].append(sum(writes.quads[first:]))
                table["ancestors"].append(len(result.recognised))
            memory.transactions.settle_view()
            rows[kind] = table
            if profile is not None:
                text = io.StringIO()
                stats = pstats.Stats(profile, stream=text)
                stats.sort_stats("tottime").print_stats(args.profile)
                profiles[kind] = text.getvalue()
        classes = len(memory.reads.classes())
        del memory, store
        gc.collect()
        return {"classes": classes, "rows": rows, "profiles": profiles}
    finally:
        for meter in recog:
            meter.remove()
        rescore.remove()
        shutil.rmtree(workdir, ignore_errors=True)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0] if __doc__ else None)
    parser.add_argument("--sizes", default="10000", help="learned classes per memory")
    parser.add_argument("--updates", type=int, default=30, help="timed updates of each kind")
    parser.add_argument("--profile", type=int, default=0, help="print the N costliest functions")
    parser.add_argument("--quick", action="store_true", help="sizes 50,200 and 5 updates")
    args = parser.parse_args()
    if args.quick:
        args.sizes, args.updates = "50,200", 5
    print("Where a scene update's time goes (bench/update_costs.py); medians, ms")
    with open("/proc/loadavg") as load:
        print(f"load average at start: {' '.join(load.read().split()[:3])}")
    print()
    header = f"{'classes':>8} {'kind':>9} " + " ".join(f"{c:>9}" for c in COLUMNS)
    print(header)
    print("-" * len(header))
    rng = random.Random(SEED)
    for size in (int(s) for s in args.sizes.split(",")):
        result = run(size, args, rng)
        rows: dict[str, dict[str, list[float]]] = result["rows"]  # type: ignore[assignment]
        for kind, table in rows.items():
            cells = " ".join(f"{statistics.median(table[c]):>9.1f}" for c in COLUMNS)
            print(f"{result['classes']:>8} {kind:>9} {cells}", flush=True)
        profiles: dict[str, str] = result["profiles"]  # type: ignore[assignment]
        for kind, text in profiles.items():
            print(f"\n{kind}s at {result['classes']} classes, by own time:")
            print("\n".join(line for line in text.splitlines()[6:] if line.strip()))
    print()
    print("recog and rescore are CPU time of the updating thread; rescore partly overlaps the")
    print("write (ScoreTable.refresh runs alongside it). ancestors = classes recognised.")


if __name__ == "__main__":
    main()
