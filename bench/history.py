"""The scene memory's history (reasoners/history.py): its cost per update, its growth, and the
"as of T" query, at 10,000 classes after 100 sleep passes.

1. ``--classes`` classes are learned with ``SceneMemory.learn_classes`` from random scenes of
   2-5 objects on an in-memory store and bulk loaded into an on-disk one (as
   bench/scene_memory.py does; not timed).
2. ``--passes`` sleep passes, each after ``--updates-per-pass`` committed scene updates and one
   retrieval, the memory clock advancing 10 minutes a pass: the history graph's growth per
   update and per pass is counted in quads and in N-Triples bytes.
3. Scene update cost with and without history, interleaved in the same run (without: the
   history functions the memory calls replaced by no-ops): ``--ab-updates`` novel
   10-object scenes (each learns a class) and as many repeats of a known scene (each
   reinforces) per side; the ratio of the medians is printed.
4. The checkpoints the passes wrote (count, bytes of their state literals), and
   ``GET /memory/as-of``'s query (``history.as_of``) at the middle pass and at the end, median
   of ``--repeats`` runs, with the checkpoints and by the full scan (interleaved; the answers
   compared), and by the analysts' SPARQL (``sparql/history_as_of.rq``, once; ``--no-sparql``
   skips it).

Run from the repository root::

    nice -n 10 .venv/bin/python bench/history.py                # 10,000 classes, 100 passes
    nice -n 10 .venv/bin/python bench/history.py --quick        # tiny, to exercise the script
"""

import argparse
import datetime as dt
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

from pyoxigraph import RdfFormat, Triple, serialize

sys.path.insert(0, str(Path(__file__).resolve().parent))
from scene_memory import build as build_memory
from scene_memory import random_scene

from kg import Store
from ontologies.vocab import (
    CHECKPOINT_STATE,
    CHECKPOINT_SUMMARY,
    EPISODIC,
    HISTORY,
    MEMORY,
    MEMORY_REVISION_GRAPH,
)
from reasoners import history
from reasoners.memory import SceneMemory

SEED = 20261126
GRAPHS = (MEMORY, EPISODIC, MEMORY_REVISION_GRAPH, HISTORY)
START = dt.datetime(2026, 1, 1, tzinfo=dt.UTC)


class Clock:
    def __init__(self) -> None:
        self.now = START

    def __call__(self) -> dt.datetime:
        return self.now


ENTRY_POINTS = ("record", "record_all", "stored", "forgetting", "sleep_levels", "checkpoint")
"""The functions of reasoners.history that reasoners.memory calls."""


class Recorder:
    """Instrumentation: every triple the history writes, kept by wrapping the functions the
    memory calls (the transaction they get is wrapped to see its inserts); ``off()`` makes them
    write nothing (the memory without history), ``on()`` records again."""

    def __init__(self) -> None:
        self.triples: list[Triple] = []
        self.originals = {name: getattr(history, name) for name in ENTRY_POINTS}
        recorder = self

        class Seen:
            def __init__(self, tx: object) -> None:
                self.tx = tx

            def __getattr__(self, name: str) -> object:  # what the functions read of it
                return getattr(self.tx, name)

            def insert(self, s: object, p: object, o: object, g: object) -> None:
                recorder.triples.append(Triple(s, p, o))  # type: ignore[arg-type]
                self.tx.insert(s, p, o, g)  # type: ignore[attr-defined]

        def wrap(function: Callable[..., object]) -> Callable[..., object]:
            def wrapped(tx: object, *args: object, **kwargs: object) -> object:
                return function(tx if isinstance(tx, Seen) else Seen(tx), *args, **kwargs)

            return wrapped

        self.wrapped = {name: wrap(f) for name, f in self.originals.items()}

    def on(self) -> None:
        for name, function in self.wrapped.items():
            setattr(history, name, function)

    def off(self) -> None:
        for name in ENTRY_POINTS:
            setattr(history, name, lambda *args, **kwargs: None)

    def restore(self) -> None:
        for name, function in self.originals.items():
            setattr(history, name, function)

    def mark(self) -> int:
        return len(self.triples)

    def since(self, mark: int) -> tuple[int, int]:
        """(quads, N-Triples bytes) written since ``mark``."""
        new = self.triples[mark:]
        return len(new), len(serialize(new, format=RdfFormat.N_TRIPLES) or b"")


def timed(call: Callable[..., object], *args: object) -> float:
    began = time.perf_counter()
    call(*args)
    return time.perf_counter() - began


def median_ms(values: list[float]) -> float:
    return statistics.median(values) * 1000


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--classes", type=int, default=10_000)
    parser.add_argument("--passes", type=int, default=100)
    parser.add_argument("--updates-per-pass", type=int, default=5)
    parser.add_argument("--ab-updates", type=int, default=30)
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument(
        "--no-sparql", action="store_true", help="skip sparql/history_as_of.rq (slow when long)"
    )
    parser.add_argument("--quick", action="store_true", help="200 classes, 10 passes")
    args = parser.parse_args()
    if args.quick:
        args.classes, args.passes, args.ab_updates, args.repeats = 200, 10, 5, 3
    rng = random.Random(SEED)
    clock = Clock()
    workdir = Path(tempfile.mkdtemp(prefix="engram-history-bench-"))
    try:
        began = time.perf_counter()
        build_memory(workdir / "store", args.classes, rng, clock=clock, graphs=GRAPHS)
        store = Store(workdir / "store")
        memory = SceneMemory(store, clock=clock)
        print(
            f"built {args.classes} classes in {time.perf_counter() - began:.0f} s; "
            f"load {os.getloadavg()[0]:.2f}"
        )
        update_growth: list[tuple[int, int]] = []
        pass_growth: list[tuple[int, int]] = []
        sleep_times: list[float] = []
        middle: dt.datetime | None = None
        recorder = Recorder()
        recorder.on()
        began = time.perf_counter()
        for number in range(args.passes):
            clock.now += dt.timedelta(minutes=10)
            for _ in range(args.updates_per_pass):
                mark = recorder.mark()
                memory.store_scene(random_scene(rng, rng.randint(3, 5)))
                update_growth.append(recorder.since(mark))
            memory.retrieve(random_scene(rng, 3))
            mark = recorder.mark()
            sleep_times.append(timed(memory.sleep))
            pass_growth.append(recorder.since(mark))
            if number == args.passes // 2:
                middle = clock.now
        recorder.restore()
        store.flush()
        quads = sum(1 for _ in store.quads(None, None, None, HISTORY))
        size = recorder.since(0)[1]
        classes = len(memory.reads.classes())
        print(
            f"{args.passes} passes in {time.perf_counter() - began:.0f} s "
            f"(sleep median {median_ms(sleep_times):.0f} ms); {classes} live classes, "
            f"{len(memory.reads.trash())} in the trash; load {os.getloadavg()[0]:.2f}"
        )
        per_update_q = statistics.median(q for q, _ in update_growth)
        per_update_b = statistics.median(b for _, b in update_growth)
        every = history.RESCORE_EVERY_PASSES
        print(
            f"history: {quads} quads in the store ({len(recorder.triples)} written during the "
            f"passes, {size / 1e6:.1f} MB as N-Triples); per scene update (median) "
            f"{per_update_q:.0f} quads, {per_update_b:.0f} bytes"
        )
        periodic = [g for i, g in enumerate(pass_growth) if (i + 1) % every == 0]
        other = [g for i, g in enumerate(pass_growth) if i and (i + 1) % every]
        print(
            f"per sleep pass: first {pass_growth[0][0]} quads ({pass_growth[0][1]} bytes); "
            f"other passes median {statistics.median(q for q, _ in other) if other else 0:.0f} "
            f"quads (max {max((q for q, _ in other), default=0)}); every {every}th pass "
            f"(rescored) median {statistics.median(q for q, _ in periodic) if periodic else 0:.0f}"
            f" quads; written per class per pass {size / classes / args.passes:.0f} bytes"
        )
        # Update cost with and without history, interleaved
        known = random_scene(rng, 10)
        memory.store_scene(known)
        store.flush()
        gc.collect()
        with_learn: list[float] = []
        without_learn: list[float] = []
        with_repeat: list[float] = []
        without_repeat: list[float] = []
        for _ in range(args.ab_updates):
            for on in (True, False):
                if on:
                    recorder.restore()
                else:
                    recorder.off()
                (with_learn if on else without_learn).append(
                    timed(memory.store_scene, random_scene(rng, 10))
                )
                (with_repeat if on else without_repeat).append(timed(memory.store_scene, known))
        recorder.restore()
        print(
            f"scene update (learn) with history {median_ms(with_learn):.2f} ms, without "
            f"{median_ms(without_learn):.2f} ms: ratio "
            f"{statistics.median(with_learn) / statistics.median(without_learn):.3f}"
        )
        print(
            f"scene update (reinforce) with history {median_ms(with_repeat):.2f} ms, without "
            f"{median_ms(without_repeat):.2f} ms: ratio "
            f"{statistics.median(with_repeat) / statistics.median(without_repeat):.3f}"
        )
        numbers = [
            history._text(q.object) or "" for q in store.quads(None, CHECKPOINT_SUMMARY, None, None)
        ]
        stored = sum(
            len(history._text(q.object) or "")
            for q in store.quads(None, CHECKPOINT_STATE, None, None)
        )
        print(
            f"checkpoints: {len(numbers)} (numbers "
            f"{sorted(int(n.split()[0]) for n in numbers)}), {stored / 1e6:.2f} MB of state "
            f"literals ({stored / max(len(numbers), 1) / 1e3:.0f} kB each), "
            f"{stored / args.passes:.0f} bytes per pass"
        )
        for label, at in (("middle pass", middle), ("end", clock.now)):
            assert at is not None
            times: dict[bool, list[float]] = {True: [], False: []}
            answers = {}
            for _ in range(args.repeats):
                for use in (True, False):
                    began = time.perf_counter()
                    answers[use] = history.as_of(store, at, use_checkpoints=use)
                    times[use].append(time.perf_counter() - began)
            same = "same answers" if answers[True] == answers[False] else "ANSWERS DIFFER"
            print(
                f"as-of at the {label}: {len(answers[True])} classes, median "
                f"{median_ms(times[True]):.0f} ms (min {min(times[True]) * 1000:.0f}) with "
                f"checkpoints, {median_ms(times[False]):.0f} ms by the full scan: ratio "
                f"{statistics.median(times[True]) / statistics.median(times[False]):.3f}, "
                f"{same}; load {os.getloadavg()[0]:.2f}"
            )
            if not args.no_sparql:  # once: it tests every class against every pass's text
                began, cpu = time.perf_counter(), time.process_time()
                rows = store.select("history_as_of", asOf=history._time_literal(at))
                wall, cpu = time.perf_counter() - began, time.process_time() - cpu
                got = sorted((r["class"].value, r["kind"].value) for r in rows)
                expected = sorted((c.cls.value, c.last_event) for c in answers[True])
                print(
                    f"  the same by sparql/history_as_of.rq: {wall * 1000:.0f} ms "
                    f"(CPU {cpu * 1000:.0f} ms), "
                    f"{'same answers' if got == expected else 'ANSWERS DIFFER'}"
                )
        del memory, store
        gc.collect()
    finally:
        shutil.rmtree(workdir, ignore_errors=True)


if __name__ == "__main__":
    main()
