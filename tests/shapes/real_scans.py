"""The vendored real scans as the tests perceive them, once per scan and seed in a session."""

import functools
import importlib.util
from pathlib import Path
from types import ModuleType

from shapes import FrameResult, Perception, PerceptionParams, open_source

SCANS = Path(__file__).parents[1] / "data" / "real_scans"


@functools.cache
def perceived(name: str, seed: int = 0) -> FrameResult:
    """``name``'s frame through the whole chain with no pose, as ``bench/perception.py`` runs it
    (gravity from the scene; ``seed`` drives the plane search)."""
    frame = next(open_source(SCANS / f"{name}.npz"))
    return Perception(PerceptionParams(gravity_from_scene=True), seed=seed).process(frame)


@functools.cache
def measure_module() -> ModuleType:
    """``tests/data/real_scans/measure.py``, the ground truth's own measuring script (numpy only,
    not a package: loaded from its path)."""
    spec = importlib.util.spec_from_file_location("real_scans_measure", SCANS / "measure.py")
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module
