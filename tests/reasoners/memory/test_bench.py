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
    # and where a learn's time and quads go, per size: write vs own work, quads by part
    after = done.stdout.split("Where a committed update's time goes")[1]
    breakdown, targets = after.split("Against the targets of issue 31")
    parts = [
        line.split() for line in breakdown.splitlines() if line.split()[:1] in (["20"], ["60"])
    ]
    assert len(parts) == 2, done.stdout
    for row in parts:
        write, own, _, _, *quads, view_learn, _, db_open, cpu_learn, _, _, cpu_open = (
            float(x) for x in row[1:-2]
        )
        assert write > 0 and own > 0 and db_open > 0 and cpu_learn > 0 and cpu_open > 0
        assert view_learn > 0  # the view of the learns, written once before the next read
        view, _edges, new_class, scene, _ = quads
        assert new_class > 0 and scene > 0 and view > 0, row
        sleep_write, sleep_quads = (float(x) for x in row[-2:])
        assert sleep_write > 0 and sleep_quads > 0, row  # the pass writes its own record
    # each measure beside the store write it commits, which cannot exceed the measure itself
    lines = [line.split() for line in targets.splitlines() if line.split()[:1] in (["20"], ["60"])]
    measures = [(line[1], line[2]) for line in lines if line[1] != "load"]
    expected = [
        ("learn", "median"),
        ("learn", "p99"),
        ("learn", "med/write"),
        ("learn", "cpu"),
        ("learn", "cpu/wcpu"),
        ("reinforce", "median"),
        ("sleep", "pass"),
        ("learn+slp", "median"),
    ]
    assert measures == expected * 2, targets
    for line in lines:
        if line[1] == "load":
            assert float(line[2]) >= 0, line
            continue
        if line[2] in ("med/write", "cpu/wcpu"):
            assert float(line[3]) >= 1, line
        else:
            figure, write = float(line[3]), float(line[4])
            assert 0 < write <= figure, line
        assert line[-1] in ("yes", "no", "-"), line  # every target beside its figure


UPDATE_COSTS = BENCH.with_name("update_costs.py")


@pytest.mark.slow
def test_update_costs_quick_prints_learn_and_reinforce_per_size() -> None:
    done = subprocess.run(
        [sys.executable, str(UPDATE_COSTS), "--quick", "--profile", "3"],
        capture_output=True,
        text=True,
        timeout=300,
        check=True,
        cwd=BENCH.parents[1],
    )
    rows = [line.split() for line in done.stdout.splitlines()]
    rows = [r for r in rows if len(r) == 9 and r[1] in ("learn", "reinforce")]
    assert [r[1] for r in rows] == ["learn", "reinforce"] * 2, done.stdout
    for row in rows:
        wall, cpu, _recog, _rescore, write, quads, ancestors = (float(x) for x in row[2:])
        assert wall > 0 and cpu > 0 and write > 0 and quads > 0, row
        assert ancestors >= 1, row  # a reinforced scene is recognised as its class at least
    assert "learns at" in done.stdout and "reinforces at" in done.stdout


def _bench(script: str, *args: str) -> str:
    done = subprocess.run(
        [sys.executable, str(BENCH.with_name(script)), *args],
        capture_output=True,
        text=True,
        timeout=300,
        check=True,
        cwd=BENCH.parents[1],
    )
    return done.stdout


def _figure(out: str, start: str) -> float:
    line = next(text for line in out.splitlines() if (text := line.strip()).startswith(start))
    return float(line[len(start) :].split()[0].rstrip("x,"))


@pytest.mark.slow
def test_learn_floor_quick_puts_the_floor_between_the_write_and_the_learn() -> None:
    out = _bench("learn_floor.py", "--quick")
    write = float(
        out.split("write by one update (Engram): wall / CPU, ms")[1].split("/")[1].split()[0]
    )
    floor = _figure(out, "floor (that work + the update's CPU), ms")
    learn_cpu = float(out.split("learn: wall / CPU (every thread), ms")[1].split("/")[1].split()[0])
    assert 0 < write < floor < learn_cpu, out


@pytest.mark.slow
def test_learn_split_builds_once_and_splits_a_learn(tmp_path: Path) -> None:
    _bench("learn_split.py", "build", "--size", "40", str(tmp_path))
    assert (tmp_path / "store.memory-index").exists()
    out = _bench("learn_split.py", "run", str(tmp_path), "--learns", "3")
    serial = _figure(out, "serial CPU (outside the write's window)")
    write = _figure(out, "store write, CPU (its thread)")
    assert serial > 0 and write > 0, out
