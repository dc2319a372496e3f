"""The vendored real scans as the tests perceive them, once per scan and seed in a session."""

import functools
import importlib.util
from pathlib import Path
from types import ModuleType

from shapes import FrameResult, Perception, PerceptionParams, open_source

SCANS = Path(__file__).parents[1] / "data" / "real_scans"
BENCH = Path(__file__).parents[2] / "bench"


@functools.cache
def perceived(name: str, seed: int = 0) -> FrameResult:
    """``name``'s frame through the whole chain with no pose, as ``bench/perception.py`` runs it
    (gravity from the scene; ``seed`` drives the plane search)."""
    frame = next(open_source(SCANS / f"{name}.npz"))
    return Perception(PerceptionParams(gravity_from_scene=True), seed=seed).process(frame)


def load_script(path: Path, name: str) -> ModuleType:
    """A script that is not part of a package (a bench script, the ground truth's measure.py),
    loaded afresh from its path as module ``name``; loading runs nothing but its definitions."""
    spec = importlib.util.spec_from_file_location(name, path)
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def bench_module(stem: str) -> ModuleType:
    """``bench/<stem>.py``, loaded afresh (tests may patch its names)."""
    return load_script(BENCH / f"{stem}.py", f"bench_{stem}")


@functools.cache
def measure_module() -> ModuleType:
    """``tests/data/real_scans/measure.py``, the ground truth's own measuring script (numpy only,
    not a package)."""
    return load_script(SCANS / "measure.py", "real_scans_measure")
