"""Fixtures of the scene-memory tests: a simulated clock, memories, and scene generators."""

import datetime as dt
import random

import pytest

from kg import Store
from kg.clock import SimulatedClock
from kg.primitive import KINDS, Primitive
from reasoners.memory import SceneMemory

START = dt.datetime(2025, 3, 1, 9, 0, tzinfo=dt.UTC)


class FakeClock(SimulatedClock):
    """A clock the test moves by hand, from :data:`START` unless given another time."""

    def __init__(self, start: dt.datetime = START) -> None:
        super().__init__(start)


@pytest.fixture
def clock() -> FakeClock:
    return FakeClock()


@pytest.fixture
def memory(clock: FakeClock) -> SceneMemory:
    """An empty scene memory on an in-memory store."""
    return SceneMemory(Store(), clock=clock)


def sphere(name: str, x: float, y: float, z: float) -> Primitive:
    return Primitive(name, "Sphere", centre=(x, y, z), radius=0.05)


def plane(name: str, x: float, y: float, z: float) -> Primitive:
    return Primitive(name, "Plane", centre=(x, y, z), axis=(0, 0, 1), hessian=-z)


def worked_example() -> list[Primitive]:
    """The reference's example: a sphere at (.3,.3,.3) above and behind a plane at (.3,.1,.1)."""
    return [sphere("S", 0.3, 0.3, 0.3), plane("P", 0.3, 0.1, 0.1)]


AXES = [(0.0, 0.0, 1.0), (1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.6, 0.0, 0.8)]
GRID = [0.0, 0.1, 0.2]


def random_scene(rng: random.Random, low: int = 2, high: int = 4) -> list[Primitive]:
    """A scene of ``low``..``high`` primitives on a coarse grid, so that relations (and hence
    signatures, recognitions and subsumptions) repeat across scenes."""
    scene = []
    for k in range(rng.randint(low, high)):
        kind = rng.choice(KINDS)
        centre = (rng.choice(GRID), rng.choice(GRID), rng.choice(GRID))
        if kind == "Sphere":
            scene.append(Primitive(f"o{k}", kind, centre=centre, radius=0.03))
        else:
            scene.append(Primitive(f"o{k}", kind, centre=centre, axis=rng.choice(AXES)))
    return scene
