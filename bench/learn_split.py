"""A learn's time split between Engram's own work and the store's write, on a memory built once.

``bench/scene_memory.py`` builds its memory every run (about 10 minutes of one core at 100,000
classes). This script builds one and keeps it, so that several checkouts can be measured on
copies of the same memory, one after the other in the same minutes::

    .venv/bin/python bench/learn_split.py build --size 100000 /tmp/memory-100k
    PYTHONPATH=<checkout> .venv/bin/python bench/learn_split.py run /tmp/memory-100k --learns 30

``build`` learns the classes as ``bench/scene_memory.py`` does (same seed, same scenes), opens
the memory once and saves its index file beside the store. ``run`` copies the store (linking
RocksDB's immutable ``.sst`` files), opens the copy from the index file, gives it its sleep pass,
then learns ``--learns`` novel 10-object scenes and prints, as medians over the learns:

- ``serial``: the CPU time of the calling thread outside the work done alongside the write;
- ``alongside``: the CPU time of the work done while the store writes (the re-scoring, the
  result), which on an idle core costs no wall time;
- ``write``: the CPU time of the store's write (its thread) and its quads;
- ``serial + max(write, alongside)``: what the learn would take on two idle cores;
- the learn's wall time (median and p99) beside the write's wall time, and the load.
"""

import argparse
import contextlib
import gc
import os
import pickle
import random
import shutil
import statistics
import sys
import tempfile
import time
from collections.abc import Callable, Iterator
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

from scene_memory import SEED, build, percentile, random_scene

from kg import Store
from kg.transaction import Transaction
from reasoners import index_file
from reasoners.memory import SceneMemory


def build_once(size: int, directory: Path) -> None:
    rng = random.Random(SEED)
    build(directory / "store", size, rng)
    (directory / "rng.pickle").write_bytes(pickle.dumps(rng.getstate()))
    memory = SceneMemory(Store(directory / "store"))
    memory.save_index()
    print(f"built {size} classes in {directory} ({memory.loaded.source})")


def _copy(source: Path, target: Path) -> None:
    target.mkdir(parents=True)
    for item in source.iterdir():
        if item.suffix == ".sst":  # RocksDB never rewrites these: link, as its checkpoints do
            os.link(item, target / item.name)
        else:
            shutil.copy2(item, target / item.name)


def run(directory: Path, learns: int) -> None:
    workdir = Path(tempfile.mkdtemp(prefix="engram-bench-"))
    try:
        _copy(directory / "store", workdir / "store")
        saved = directory / ("store" + index_file.SUFFIX)
        if saved.exists():
            shutil.copy2(saved, workdir / saved.name)
        rng = random.Random()
        rng.setstate(pickle.loads((directory / "rng.pickle").read_bytes()))
        store = Store(workdir / "store")
        memory = SceneMemory(store)
        store.flush()
        gc.freeze()
        novel = [random_scene(rng, 10) for _ in range(learns)]
        memory.store_scene(random_scene(rng, 10))
        memory.sleep()
        memory.transactions.settle_view()
        gc.collect()
        now: dict[str, float] = {}
        prepare = store._prepare

        def measured_prepare(tx: Transaction) -> Callable[[], None]:
            write = prepare(tx)
            now["quads"] = len(tx.inserts) + len(tx.deletes)

            def measured_write() -> None:
                began, cpu = time.perf_counter(), time.thread_time()
                write()
                now["write"] = time.thread_time() - cpu
                now["write_wall"] = time.perf_counter() - began

            return measured_write

        store._prepare = measured_prepare  # type: ignore[method-assign]
        transaction = store.transaction

        @contextlib.contextmanager
        def measured_transaction(
            *, alongside: Callable[[], object] | None = None
        ) -> Iterator[Transaction]:
            work = alongside
            if work is not None:

                def alongside() -> None:
                    began = time.thread_time()
                    work()
                    now["alongside"] = time.thread_time() - began

            with transaction(alongside=alongside) as tx:
                yield tx

        store.transaction = measured_transaction  # type: ignore[method-assign]
        rows = []
        for scene in novel:
            now.clear()
            began, cpu = time.perf_counter(), time.thread_time()
            memory.store_scene(scene)
            now["main"] = time.thread_time() - cpu
            now["wall"] = time.perf_counter() - began
            rows.append(dict(now))
        med = statistics.median

        def ms(key: str) -> float:
            return 1000 * med(r.get(key, 0.0) for r in rows)

        serial = 1000 * med(r["main"] - r.get("alongside", 0.0) for r in rows)
        walls = [1000 * r["wall"] for r in rows]
        print(f"classes {len(memory.loaded.model.graph.classes)}, {learns} learns (medians, ms)")
        print(f"  serial CPU (outside the write's window)   {serial:8.2f}")
        print(f"  alongside the write, CPU                  {ms('alongside'):8.2f}")
        quads = med(r["quads"] for r in rows)
        write = ms("write")
        idle = serial + max(write, ms("alongside"))  # the learn on two idle cores
        print(f"  store write, CPU (its thread)             {write:8.2f}  ({quads:.0f} quads)")
        print(
            f"  serial + max(write, alongside)            {idle:8.2f}  "
            f"({idle / write:.2f}x the write)"
        )
        print(
            f"  learn wall median / p99                   {med(walls):8.1f} / "
            f"{percentile(walls, 0.99):.1f}; its write's wall {ms('write_wall'):.1f}"
        )
        print(f"  load average {os.getloadavg()}")
    finally:
        shutil.rmtree(workdir, ignore_errors=True)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0] if __doc__ else None)
    commands = parser.add_subparsers(dest="command", required=True)
    making = commands.add_parser("build", help="build a memory and keep it in DIR")
    making.add_argument("directory", type=Path)
    making.add_argument("--size", type=int, default=10_000, help="learned classes")
    timing = commands.add_parser("run", help="learn on a copy of the memory in DIR")
    timing.add_argument("directory", type=Path)
    timing.add_argument("--learns", type=int, default=30, help="timed learns")
    args = parser.parse_args()
    if args.command == "build":
        build_once(args.size, args.directory)
    else:
        run(args.directory, args.learns)


if __name__ == "__main__":
    main()
