"""The read barrier's view write with typed score terms against the packed string they replaced.

A memory of ``--size`` learned classes is built once (``bench/scene_memory.py``'s ``build``) and
copied twice. On each copy the same seeded rounds run: ``--learns`` novel 10-object scenes (each
learns a class), then the read barrier (``Transactions.settle_view``), which writes the score view
those learns changed; then as many reinforces of one known scene and the barrier again. One copy
writes the view as this code does (``engram:scoreTermComplexity``, ``scoreTermStore``,
``scoreTermRetrieve``: one ``xsd:double`` each, only the terms that changed); the other as Engram
did before (one ``engram:scoreTerms "Z_d Z_s Z_r"`` string per changed class). The copies
alternate round by round, so both see the same load. Printed: the median barrier time and
its quads per round, for each layout, and typed / packed, in wall and in CPU time (every
thread of the process; steadier under load).

Run from the repository root::

    PYTHONPATH=. .venv/bin/python bench/score_terms.py --size 10000 --rounds 4
"""

import argparse
import os
import random
import shutil
import statistics
import sys
import tempfile
import time
from pathlib import Path

from pyoxigraph import Literal, NamedNode

sys.path.insert(0, str(Path(__file__).resolve().parent))

import scene_memory as bench

from kg import Store
from kg.transaction import Transaction
from ontologies.vocab import MEMORY, SCORE_TERMS
from reasoners import persist
from reasoners.memory import SceneMemory
from reasoners.model import MemoryModel
from reasoners.score_table import SCALE

TYPED = persist.write_view


def packed(z: tuple[int, int, int]) -> Literal:
    return Literal(f"{z[0] / SCALE!r} {z[1] / SCALE!r} {z[2] / SCALE!r}")


def write_packed_view(tx: Transaction, model: MemoryModel, policy: NamedNode) -> int:
    """The view as Engram wrote it before typed terms: one string per changed class."""
    model.scores.refresh()
    rewritten = 0
    for iri in sorted(model.scores.unwritten, key=lambda i: i.value):
        record = model.graph.classes.get(iri)
        if record is None or record.written_z == record.z:
            continue
        if record.written_z is not None:
            tx.delete(iri, SCORE_TERMS, packed(record.written_z), MEMORY)
        tx.insert(iri, SCORE_TERMS, packed(record.z), MEMORY)
        record.written_z = record.z
        rewritten += 1
    model.scores.unwritten.clear()
    TYPED(tx, model, policy)  # the factors on the memory state, the same in both layouts
    return rewritten


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0] if __doc__ else None)
    parser.add_argument("--size", type=int, default=10_000, help="learned classes")
    parser.add_argument("--rounds", type=int, default=4, help="rounds per layout")
    parser.add_argument("--learns", type=int, default=10, help="learns (and reinforces) a round")
    args = parser.parse_args()
    print("Score view write at the read barrier: typed terms vs the packed string")
    print(f"load average at the start: {os.getloadavg()}")
    workdir = Path(tempfile.mkdtemp(prefix="engram-terms-"))
    try:
        bench.build(workdir / "built", args.size, random.Random(bench.SEED))
        memories = {}
        for layout in ("typed", "packed"):
            shutil.copytree(workdir / "built", workdir / layout)
            store = Store(workdir / layout)
            if layout == "packed":  # first as the packed layout held it
                persist.write_view = write_packed_view  # type: ignore[assignment]
            memory = SceneMemory(store)
            persist.write_view = TYPED
            timer = bench.WriteTimer(store)
            memories[layout] = (memory, timer, random.Random(7), [], [])
        known = bench.random_scene(random.Random(8), 10)
        for _ in range(args.rounds):
            for layout, (memory, timer, rng, learns, repeats) in memories.items():
                persist.write_view = write_packed_view if layout == "packed" else TYPED  # type: ignore[assignment]
                for scenes, out in (
                    ([bench.random_scene(rng, 10) for _ in range(args.learns)], learns),
                    ([known] * args.learns, repeats),
                ):
                    for scene in scenes:
                        memory.store_scene(scene)
                    first = len(timer.quads)
                    began, cpu = time.perf_counter(), time.process_time()
                    memory.transactions.settle_view()
                    wall, cpu = time.perf_counter() - began, time.process_time() - cpu
                    out.append((wall, sum(timer.quads[first:]), cpu))
                persist.write_view = TYPED
        print(f"{args.size} classes, {args.rounds} rounds of {args.learns} updates per layout")
        print(
            f"{'after':<10} {'layout':<7} {'median ms':>10} {'quads':>7} {'x packed':>9} "
            f"{'CPU ms':>8} {'x packed':>9}"
        )
        for k, name in ((3, "learns"), (4, "reinforces")):
            base = statistics.median(t for t, _, _ in memories["packed"][k])
            base_cpu = statistics.median(c for _, _, c in memories["packed"][k])
            for layout in ("typed", "packed"):
                runs = memories[layout][k]
                median = statistics.median(t for t, _, _ in runs)
                quads = statistics.median(q for _, q, _ in runs)
                cpu = statistics.median(c for _, _, c in runs)
                print(
                    f"{name:<10} {layout:<7} {1000 * median:>10.1f} {quads:>7.0f} "
                    f"{median / base:>9.2f} {1000 * cpu:>8.1f} {cpu / base_cpu:>9.2f}"
                )
        print(f"load average at the end: {os.getloadavg()}")
    finally:
        persist.write_view = TYPED
        shutil.rmtree(workdir, ignore_errors=True)


if __name__ == "__main__":
    main()
