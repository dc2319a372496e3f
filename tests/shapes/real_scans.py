"""The vendored real scans as the tests perceive them, once per scan and seed in a session."""

import functools
from pathlib import Path

from shapes import FrameResult, Perception, PerceptionParams, open_source

SCANS = Path(__file__).parents[1] / "data" / "real_scans"


@functools.cache
def perceived(name: str, seed: int = 0) -> FrameResult:
    """``name``'s frame through the whole chain with no pose, as ``bench/perception.py`` runs it
    (gravity from the scene; ``seed`` drives the plane search)."""
    frame = next(open_source(SCANS / f"{name}.npz"))
    return Perception(PerceptionParams(gravity_from_scene=True), seed=seed).process(frame)
