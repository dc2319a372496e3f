"""The benchmark script runs (at tiny sizes) and prints one row per memory size."""

import subprocess
import sys
from pathlib import Path

import pytest

BENCH = Path(__file__).resolve().parents[3] / "bench" / "scene_memory.py"


@pytest.mark.slow
def test_bench_quick_prints_a_row_per_size() -> None:
    done = subprocess.run(
        [sys.executable, str(BENCH), "--quick", "--no-hermit"],
        capture_output=True,
        text=True,
        timeout=300,
        check=True,
        cwd=BENCH.parents[1],
    )
    rows = [line for line in done.stdout.splitlines() if line.strip().startswith(("20/", "60/"))]
    assert len(rows) == 2, done.stdout
