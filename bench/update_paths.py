"""Where a reinforce's and a learn's time goes on a large memory, in CPU time (load-proof).

``bench/scene_memory.py`` times whole updates in wall time, which on a shared machine mostly
measures the wait for a core. This script splits an update by thread instead, on a copy of a
memory built once (``--build``):

- **reinforce** (the known scene again) and **learn** (novel 10-object scenes): the caller's
  CPU outside the store's write, the CPU of the work beside the write (``alongside``: the
  ancestors' re-scoring and, for a reinforce, the list of recognised classes), the writer
  thread's CPU, and the critical path ``outside + max(alongside, write)``: the update's time on
  a machine with a free core for each thread;
- **the slowest learns**: each one's CPU, store write and quads beside its number of direct
  parents and recognised classes;
- **learns right after a sleep pass** against learns in the store just flushed ("settled"),
  by the writer thread's CPU, and wall time.

Run from the repository root (``--build`` takes minutes of one core at 100,000 classes)::

    PYTHONPATH=. .venv/bin/python bench/update_paths.py --build 100000 --dir /tmp/m100k
    PYTHONPATH=. .venv/bin/python bench/update_paths.py --dir /tmp/m100k --updates 20

To compare two checkouts, run the second command with ``PYTHONPATH`` set to each.
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

sys.path.insert(0, str(Path(__file__).parent))
from scene_memory import SEED, WriteTimer, build, random_scene

from kg import Store
from kg.primitive import Primitive
from kg.transaction import Transaction
from reasoners.memory import SceneMemory


def build_memory(size: int, directory: Path) -> None:
    """A memory of ``size`` classes (``scene_memory.build``), the known scene stored once, its
    first sleep pass and its index file, under ``directory``."""
    rng = random.Random(SEED)
    build(directory / "store", size, rng)
    memory = SceneMemory(Store(directory / "store"))
    known = random_scene(rng, 10)
    (directory / "known.pickle").write_bytes(pickle.dumps(known))
    memory.store_scene(known)
    memory.sleep()
    memory.save_index()


class ThreadClock:
    """The CPU of the store's writer thread and of the work beside it, per transaction."""

    def __init__(self, store: Store) -> None:
        self.write: list[float] = []
        self.alongside: list[float] = []
        prepare, transaction = store._prepare, store.transaction

        def timed_prepare(tx: Transaction) -> Callable[[], None]:
            write = prepare(tx)

            def timed_write() -> None:
                began = time.thread_time()
                write()
                self.write.append(time.thread_time() - began)

            return timed_write

        @contextlib.contextmanager
        def timed_transaction(
            *, alongside: Callable[[], object] | None = None
        ) -> Iterator[Transaction]:
            work = alongside

            def timed_alongside() -> None:
                began = time.thread_time()
                work()  # type: ignore[misc]
                self.alongside.append(time.thread_time() - began)

            with transaction(alongside=timed_alongside if work else None) as tx:
                yield tx

        store._prepare = timed_prepare  # type: ignore[method-assign]
        store.transaction = timed_transaction  # type: ignore[method-assign]


def split(memory: SceneMemory, clock: ThreadClock, scenes: list[list[Primitive]]) -> str:
    outside, beside, writes, critical = [], [], [], []
    for scene in scenes:
        clock.write.clear()
        clock.alongside.clear()
        began = time.thread_time()
        memory.store_scene(scene)
        total = time.thread_time() - began
        a, w = sum(clock.alongside), sum(clock.write)
        outside.append(total - a)
        beside.append(a)
        writes.append(w)
        critical.append(total - a + max(a, w))

    def ms(values: list[float]) -> str:
        return f"{1000 * statistics.median(values):7.2f}"

    return (
        f"outside {ms(outside)}  alongside {ms(beside)}  write {ms(writes)}  "
        f"critical {ms(critical)} (max {1000 * max(critical):.2f})"
    )


def learns(memory: SceneMemory, timer: WriteTimer, clock: ThreadClock, scenes: list) -> str:  # type: ignore[type-arg]
    walls, cpus = [], []
    first = len(clock.write)
    for scene in scenes:
        began, cpu = time.perf_counter(), time.process_time()
        memory.store_scene(scene)
        walls.append(time.perf_counter() - began)
        cpus.append(time.process_time() - cpu)
    written = clock.write[first:]
    return (
        f"wall {1000 * statistics.median(walls):8.1f}  process CPU "
        f"{1000 * statistics.median(cpus):7.1f}  writer thread CPU "
        f"{1000 * statistics.median(written):6.1f}"
    )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0] if __doc__ else None)
    parser.add_argument("--dir", type=Path, required=True, help="the memory built by --build")
    parser.add_argument("--build", type=int, metavar="SIZE", help="build a memory of SIZE classes")
    parser.add_argument("--updates", type=int, default=20, help="timed updates of each kind")
    args = parser.parse_args()
    if args.build:
        build_memory(args.build, args.dir)
        return
    print(f"load average at the start: {os.getloadavg()}")
    work = Path(tempfile.mkdtemp(prefix="engram-paths-"))
    try:
        for path in args.dir.iterdir():
            if path.name.startswith("store"):
                (shutil.copytree if path.is_dir() else shutil.copy2)(path, work / path.name)
        known = pickle.loads((args.dir / "known.pickle").read_bytes())
        store = Store(work / "store")
        memory = SceneMemory(store)
        print(f"{len(memory.loaded.model.classes)} classes ({memory.loaded.source})")
        store.flush()
        gc.freeze()
        timer, clock = WriteTimer(store), ThreadClock(store)
        rng = random.Random(5)
        memory.store_scene(known)
        memory.transactions.settle_view()
        print("reinforce  ", split(memory, clock, [known] * args.updates))
        memory.transactions.settle_view()
        store.flush()
        novel = [random_scene(rng, 10) for _ in range(args.updates)]
        print("learn      ", split(memory, clock, novel))
        rows = []
        for scene in (random_scene(rng, 10) for _ in range(args.updates)):
            began = time.thread_time()
            result = memory.store_scene(scene)
            rows.append(
                (
                    1000 * (time.thread_time() - began),
                    1000 * clock.write[-1],
                    timer.quads[-1],
                    len(result.parents),
                    len(result.recognised),
                )
            )
        print("the slowest learns: caller CPU, writer CPU (ms), quads, parents, recognised")
        for row in sorted(rows, reverse=True)[:3] + sorted(rows)[:1]:
            print("   {:8.1f} {:8.1f} {:6d} {:6d} {:7d}".format(*row))
        memory.transactions.settle_view()
        store.flush()
        settled = [random_scene(rng, 10) for _ in range(args.updates)]
        print("settled    ", learns(memory, timer, clock, settled))
        for _ in range(args.updates):
            memory.store_scene(known)
        memory.transactions.settle_view()
        began = time.perf_counter()
        memory.sleep()
        print(f"sleep pass  wall {1000 * (time.perf_counter() - began):.0f} ms")
        after = [random_scene(rng, 10) for _ in range(args.updates)]
        print("after pass ", learns(memory, timer, clock, after))
        print(f"load average at the end: {os.getloadavg()}")
        del memory, store
        gc.unfreeze()
        gc.collect()
    finally:
        shutil.rmtree(work, ignore_errors=True)


if __name__ == "__main__":
    main()
