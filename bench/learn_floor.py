"""How close a learn is to the cheapest atomic write of its own quads.

A memory of ``--size`` classes is built as ``bench/scene_memory.py`` builds it (on disk,
flushed, after its first sleep pass), then ``--learns`` novel 10-object scenes are learned. Each
learn's transaction is written in one of two ways, alternating learn by learn:

- ``update``: as Engram writes it, one SPARQL update (``DELETE DATA``/``INSERT DATA``), the only
  atomic write of deletions and insertions that pyoxigraph offers (``Store.update``);
- ``extend``: ``Store.extend`` of the insertions, then an update of the few deletions: two
  writes, not atomic, so never what Engram does; it shows what parsing the update costs.

For each, the medians of the write's wall and CPU time (the writing thread's), beside the
learn's own wall and CPU time (every thread), and the Python work that any atomic write of those
quads needs: building the ``Quad`` objects from their terms and the update's text (both timed
on the learn's own quads, after it). ``floor`` is that work plus the ``update`` write: a learn
that did nothing else (no encoding, no recognition, no placing) would take that long.

Run from the repository root::

    .venv/bin/python bench/learn_floor.py --size 10000 --learns 40
    .venv/bin/python bench/learn_floor.py --quick       # tiny, to exercise the script
"""

import argparse
import gc
import os
import random
import shutil
import statistics
import sys
import tempfile
import time
from collections.abc import Callable
from pathlib import Path

from pyoxigraph import Quad

sys.path.insert(0, str(Path(__file__).resolve().parent))

from scene_memory import SEED, build, random_scene

from kg import Store
from kg.literals import quads_to_store
from kg.store import update_text
from kg.transaction import Transaction
from reasoners.memory import SceneMemory


def _cpu_ms(call: Callable[[], object]) -> float:
    began = time.thread_time()
    call()
    return 1000 * (time.thread_time() - began)


def run(size: int, learns: int) -> dict[str, list[float]]:
    rng = random.Random(SEED)
    workdir = Path(tempfile.mkdtemp(prefix="engram-bench-"))
    figures: dict[str, list[float]] = {
        k: []
        for k in (
            "learn",
            "learn_cpu",
            "update",
            "update_cpu",
            "extend",
            "extend_cpu",
            "quads",
            "build_quads_cpu",
            "text_cpu",
        )
    }
    try:
        build(workdir / "store", size, rng)
        store = Store(workdir / "store")
        memory = SceneMemory(store)
        store.flush()
        gc.freeze()
        memory.store_scene(random_scene(rng, 10))
        memory.sleep()
        memory.transactions.settle_view()
        gc.collect()
        raw = store._store
        written: list[Transaction] = []
        prepare = store._prepare

        def measured_prepare(tx: Transaction) -> Callable[[], None]:
            engram_write = prepare(tx)  # Engram's own write (its text built here)
            inserts, deletes = quads_to_store(tx.inserts), quads_to_store(tx.deletes)
            for pattern in tx.patterns:
                deletes.extend(
                    raw.quads_for_pattern(
                        pattern.subject, pattern.predicate, pattern.object, pattern.graph
                    )
                )
            by_extend = len(written) % 2 == 1
            written.append(tx)

            def write() -> None:
                began, cpu = time.perf_counter(), time.thread_time()
                if by_extend:
                    raw.extend(inserts)
                    if deletes:
                        raw.update(update_text([], deletes, []))
                    store._generation += 1
                else:
                    engram_write()
                kind = "extend" if by_extend else "update"
                figures[kind + "_cpu"].append(1000 * (time.thread_time() - cpu))
                figures[kind].append(1000 * (time.perf_counter() - began))

            return write

        store._prepare = measured_prepare  # type: ignore[method-assign]
        for _ in range(learns):
            scene = random_scene(rng, 10)
            began, cpu = time.perf_counter(), time.process_time()
            memory.store_scene(scene)
            figures["learn_cpu"].append(1000 * (time.process_time() - cpu))
            figures["learn"].append(1000 * (time.perf_counter() - began))
        for tx in written:
            quads = [*tx.inserts, *tx.deletes]
            terms = [(q.subject, q.predicate, q.object, q.graph_name) for q in quads]
            figures["quads"].append(len(quads))
            figures["build_quads_cpu"].append(_cpu_ms(lambda t=terms: [Quad(*x) for x in t]))  # type: ignore[misc]
            figures["text_cpu"].append(
                _cpu_ms(lambda tx=tx: update_text(tx.cleared, tx.deletes, tx.inserts))  # type: ignore[misc]
            )
        gc.unfreeze()
        return figures
    finally:
        shutil.rmtree(workdir, ignore_errors=True)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0] if __doc__ else None)
    parser.add_argument("--size", type=int, default=10_000, help="learned classes")
    parser.add_argument("--learns", type=int, default=40, help="timed learns (half each way)")
    parser.add_argument("--quick", action="store_true", help="60 classes, 6 learns")
    args = parser.parse_args()
    if args.quick:
        args.size, args.learns = 60, 6
    print(f"bench/learn_floor.py, {args.size} classes; load average at the start: ", end="")
    print(os.getloadavg())
    f = run(args.size, args.learns)
    med = statistics.median
    update, update_cpu = med(f["update"]), med(f["update_cpu"])
    python_floor = med(f["build_quads_cpu"]) + med(f["text_cpu"])
    print(f"quads a learn (median)                        {med(f['quads']):9.0f}")
    learn, learn_cpu = med(f["learn"]), med(f["learn_cpu"])
    print(f"learn: wall / CPU (every thread), ms          {learn:9.2f} / {learn_cpu:.2f}")
    print(f"write by one update (Engram): wall / CPU, ms  {update:9.2f} / {update_cpu:.2f}")
    print(
        f"extend + update of the deletions (2 writes)   {med(f['extend']):9.2f} / "
        f"{med(f['extend_cpu']):.2f}"
    )
    print(f"Python work of any atomic write: Quads + text {python_floor:9.2f} CPU ms")
    print(
        f"floor (that work + the update's CPU), ms      {python_floor + update_cpu:9.2f}, "
        f"{(python_floor + update_cpu) / update_cpu:.2f}x the write"
    )
    print(
        f"learn CPU / write CPU                         {learn_cpu / update_cpu:9.2f}x"
        f"  (the target: <= 1.3x; learn wall / write wall {learn / update:.2f}x)"
    )
    print(f"load average at the end: {os.getloadavg()}")


if __name__ == "__main__":
    main()
