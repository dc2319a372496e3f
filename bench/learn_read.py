"""The CPU time of a learn, and of a learn followed by a read (which first writes the score view
the learn changed), for this code and for another checkout, alternating on copies of one memory.

A memory of ``--size`` classes is built once (``bench/scene_memory.py``'s ``build``, by this
code); each round copies it for each side and runs, in a subprocess whose ``PYTHONPATH`` is that
side's tree: one scene stored and a sleep pass, then ``--learns`` seeded novel 10-object scenes,
each followed by the read barrier (the view write) with ``--read``. Printed per side and round:
the median CPU time (every thread of the process) of one learn (and read), and of the store's
writes alone (Oxigraph applying the learn's transaction, the view's), and their quads. Under a
shared machine's load, CPU times compare where wall times do not.

Run from the repository root::

    PYTHONPATH=. .venv/bin/python bench/learn_read.py --against /path/to/checkout --read
"""

import argparse
import gc
import os
import random
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

HERE = Path(__file__).resolve()


def measure(store_dir: Path, learns: int, read: bool) -> None:
    """In the subprocess: the measurements of one side, printed as one line."""
    sys.path.insert(0, str(HERE.parent))
    import scene_memory as bench  # the side's own bench helpers (its tree's API)

    from kg import Store
    from reasoners.memory import SceneMemory

    store = Store(store_dir)
    memory = SceneMemory(store)
    barrier = getattr(memory, "transactions", memory).settle_view  # before / after the split
    store.flush()
    gc.freeze()  # as the server does once the memory has loaded
    rng = random.Random(7)
    scenes = [bench.random_scene(rng, 10) for _ in range(learns)]
    memory.store_scene(bench.random_scene(rng, 10))
    memory.sleep()
    barrier()
    gc.collect()
    writes: list[tuple[float, int]] = []
    prepare = store._prepare

    def timed_prepare(tx: object) -> object:
        write, quads = prepare(tx), len(tx.inserts) + len(tx.deletes)  # type: ignore[attr-defined]

        def timed_write() -> None:
            began = time.thread_time()
            write()
            writes.append((time.thread_time() - began, quads))

        return timed_write

    store._prepare = timed_prepare
    cpu = []
    for scene in scenes:
        began = time.process_time()
        memory.store_scene(scene)
        if read:
            barrier()
        cpu.append(time.process_time() - began)
    learn = writes[0::2] if read else writes
    view = writes[1::2] if read else []
    med = statistics.median
    figures = [
        1000 * med(cpu),
        1000 * med(w for w, _ in learn),
        med(q for _, q in learn),
        1000 * med(w for w, _ in view) if view else 0.0,
        med(q for _, q in view) if view else 0,
    ]
    print(" ".join(f"{x:.1f}" for x in figures), flush=True)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0] if __doc__ else None)
    parser.add_argument("--against", required=True, help="the other checkout's root")
    parser.add_argument("--size", type=int, default=10_000, help="learned classes")
    parser.add_argument("--learns", type=int, default=30, help="timed learns per side and round")
    parser.add_argument("--rounds", type=int, default=2)
    parser.add_argument("--read", action="store_true", help="a read after each learn")
    parser.add_argument("--measure", help=argparse.SUPPRESS)  # the subprocess's store
    args = parser.parse_args()
    if args.measure:
        measure(Path(args.measure), args.learns, args.read)
        return
    sys.path.insert(0, str(HERE.parent))
    import scene_memory as bench

    sides = {"this": HERE.parents[1], "against": Path(args.against).resolve()}
    print(f"learn{' + read' if args.read else ''}: CPU ms (medians), {args.size} classes")
    print(f"load average at the start: {os.getloadavg()}")
    workdir = Path(tempfile.mkdtemp(prefix="engram-learn-read-"))
    try:
        bench.build(workdir / "built", args.size, random.Random(bench.SEED))
        print(
            f"{'round':>5} {'side':<8} {'cpu':>8} {'lrn wr':>8} {'quads':>6} {'view wr':>8} "
            f"{'quads':>6} {'load':>6}"
        )
        for number in range(args.rounds):
            for name, tree in sides.items():
                shutil.rmtree(workdir / "copy", ignore_errors=True)
                shutil.copytree(workdir / "built", workdir / "copy")
                # this script measures both sides, each importing its own tree's code
                command = [sys.executable, str(HERE), "--against", ".", "--measure"]
                command += [str(workdir / "copy")]
                command += ["--learns", str(args.learns)] + (["--read"] if args.read else [])
                env = {**os.environ, "PYTHONPATH": str(tree)}
                line = subprocess.run(
                    command, env=env, cwd=tree, check=True, capture_output=True, text=True
                ).stdout.split()
                print(
                    f"{number:>5} {name:<8} {line[0]:>8} {line[1]:>8} {line[2]:>6} {line[3]:>8} "
                    f"{line[4]:>6} {os.getloadavg()[0]:>6.2f}",
                    flush=True,
                )
    finally:
        shutil.rmtree(workdir, ignore_errors=True)
    print("cpu = a learn (and its read); lrn wr, view wr = the store applying the learn's and")
    print("the view's transactions alone (CPU of the writing thread), with their quads.")


if __name__ == "__main__":
    main()
