"""How long ``import api.client`` takes, against the floor of the libraries it needs.

The robot-side client needs pydantic and httpx only (``tests/api/test_client_imports.py``);
it imports httpx, and pydantic with the wire protocol's models when it builds its first
directive. What the import costs beyond httpx is ours. Each figure is the median of ``--runs``
fresh interpreters (this one, ``sys.executable``, or ``--python``), each importing one thing:

- ``api.client``: the client, as a robot program imports it;
- ``api.client, first directive``: the import and the first directive built (pydantic and the
  protocol's models loaded then): what a program pays before its first call leaves;
- floor ``httpx``: what the import needs;
- floor ``httpx, pydantic``: the two libraries alone (``import pydantic`` loads little by
  itself: pydantic imports its parts when they are first asked for);
- floor ``httpx, a pydantic model``: the two libraries as any pydantic model needs them (the
  first model class loads most of pydantic: its types, validators, plugin discovery).

Two measures each: the import's own line of ``python -X importtime`` (wall clock, so it moves
with the machine's load) and the child's CPU time around the ``import`` statement
(``time.process_time``, which moves much less). The children write and read their compiled
bytecode in a temporary ``PYTHONPYCACHEPREFIX``, warmed by one run first, so that an
environment with ``PYTHONDONTWRITEBYTECODE`` measures the same as an installed one.

Run from the repository root, in the full environment and in one with the client's two
libraries only::

    .venv/bin/python bench/imports.py
    python -m venv /tmp/clientvenv && /tmp/clientvenv/bin/pip install pydantic==X httpx==Y
    .venv/bin/python bench/imports.py --python /tmp/clientvenv/bin/python
    .venv/bin/python bench/imports.py --against ../other-checkout    # its api.client too

On a loaded machine the importtime figures grow with the load; the CPU figures and the
difference to the floor much less.
"""

import argparse
import os
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))
from bench.timing import load_average  # noqa: E402

TARGET_MS = 100.0
SUBJECTS = {
    "api.client": "import api.client",
    "api.client, first directive": (
        "import api.client\n"
        "api.client.ArmorClient('c', 'r', base_url='http://127.0.0.1:9')"
        "._request('ADD', 'IND', '', ['x'])"
    ),
    "floor: httpx": "import httpx",
    "floor: httpx, pydantic": "import httpx, pydantic",
    "floor: httpx, a pydantic model": (
        "import httpx\nfrom pydantic import BaseModel, ConfigDict\n"
        "class Model(BaseModel):\n    model_config = ConfigDict(defer_build=True)\n    x: int = 0"
    ),
}
PROBE = """
import time
started = time.process_time()
{statement}
print(time.process_time() - started)
"""


def _once(python: str, statement: str, cache: str, root: Path = ROOT) -> tuple[float, float]:
    """(importtime ms of the statement's imports, CPU ms) in a fresh interpreter, with the
    checkout at ``root`` on its path."""
    env = {
        **os.environ,
        "PYTHONPATH": str(root),
        "PYTHONPYCACHEPREFIX": cache,
        "PYTHONDONTWRITEBYTECODE": "",
    }
    env.pop("PYTHONDONTWRITEBYTECODE")
    done = subprocess.run(
        [python, "-X", "importtime", "-c", PROBE.format(statement=statement)],
        capture_output=True,
        text=True,
        check=True,
        cwd=root,
        env=env,
    )
    cpu_ms = 1000 * float(done.stdout.strip())
    # the top-level lines (no indentation) after the interpreter's start-up are the statement's
    lines = [line for line in done.stderr.splitlines() if line.startswith("import time:")]
    start = max(i for i, line in enumerate(lines) if line.rstrip().endswith("| site")) + 1
    top = [line for line in lines[start:] if not line.split("|")[2].startswith("  ")]
    wall_ms = sum(int(line.split("|")[1]) for line in top) / 1000
    return wall_ms, cpu_ms


def measure(python: str, runs: int, other: Path | None) -> dict[str, tuple[float, float]]:
    """Median (importtime ms, CPU ms) of each subject, the subjects taken in turns; with
    ``other``, ``api.client`` of that checkout too."""
    subjects = {name: (statement, ROOT) for name, statement in SUBJECTS.items()}
    if other is not None:
        subjects[f"api.client of {other}"] = (SUBJECTS["api.client"], other)
    figures: dict[str, list[tuple[float, float]]] = {name: [] for name in subjects}
    with tempfile.TemporaryDirectory(prefix="engram-pycache-") as cache:
        for statement, root in subjects.values():
            _once(python, statement, cache, root)  # compile once, as an installed package is
        for _ in range(runs):
            for name, (statement, root) in subjects.items():
                figures[name].append(_once(python, statement, cache, root))
    return {
        name: (statistics.median(w for w, _ in runs_), statistics.median(c for _, c in runs_))
        for name, runs_ in figures.items()
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--python", default=sys.executable, help="the interpreter to measure")
    parser.add_argument("--runs", type=int, default=9, help="fresh interpreters per figure")
    parser.add_argument("--against", type=Path, metavar="CHECKOUT", help="its api.client too")
    options = parser.parse_args()
    version = subprocess.run(
        [
            options.python,
            "-c",
            "import httpx, pydantic; print(httpx.__version__, pydantic.VERSION)",
        ],
        capture_output=True,
        text=True,
        check=True,
    ).stdout.split()
    print(f"# import api.client: {options.python} (httpx {version[0]}, pydantic {version[1]})")
    print(f"  {load_average()}")
    figures = measure(options.python, options.runs, options.against)
    for name, (wall, cpu) in figures.items():
        print(
            f"  {name:40s} importtime {wall:6.1f} ms   CPU {cpu:6.1f} ms"
            f"  (median of {options.runs})"
        )
    wall, cpu = figures["api.client"]
    floor_wall, floor_cpu = figures["floor: httpx"]
    verdict = "met" if wall < TARGET_MS else "NOT met"
    print(
        f"  target importtime < {TARGET_MS:.0f} ms: {verdict}; ours above the floor: "
        f"{wall - floor_wall:.1f} ms importtime, {cpu - floor_cpu:.1f} ms CPU"
    )
    print(f"  {load_average()}")


if __name__ == "__main__":
    main()
