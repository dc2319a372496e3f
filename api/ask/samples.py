"""A lived week to ask, and the questions the speech tests and ``bench/ask.py`` ask it (as the
synthetic clouds of :mod:`shapes.synthetic` serve tests, demo and benchmarks).

The clock runs from Monday 2026-03-02 08:00 UTC and stops at Wednesday 2026-03-04 10:00.
``python -m api.ask.samples DIR`` writes the week into the data directory ``DIR`` (the README's
``engram ask --data DIR ...`` examples ask it).
"""

import argparse
import datetime as dt
import gc
import sys
from pathlib import Path

from episodes import ArgumentSpec, EpisodeMemory
from kg import Store, ensure_ontology
from kg.clock import SimulatedClock
from kg.primitive import Primitive
from reasoners.memory import SceneMemory

__all__ = ["EPISODES", "NOW", "SPOKEN", "START", "live_a_week", "main"]

START = dt.datetime(2026, 3, 2, 8, 0, tzinfo=dt.UTC)
NOW = dt.datetime(2026, 3, 4, 10, 0, tzinfo=dt.UTC)


def sphere(name: str, x: float, y: float, z: float) -> Primitive:
    return Primitive(name, "Sphere", centre=(x, y, z), radius=0.05)


def plane(name: str, x: float, y: float, z: float) -> Primitive:
    return Primitive(name, "Plane", centre=(x, y, z), axis=(0, 0, 1), hessian=-z)


def cone(name: str, x: float, y: float, z: float) -> Primitive:
    return Primitive(name, "Cone", centre=(x, y, z), axis=(0, 0, 1), radius=0.05, height=0.1)


BALL_ON_TABLE = [sphere("ball", 0.3, 0.3, 0.3), plane("table", 0.3, 0.1, 0.1)]
TWO_BALLS = [*BALL_ON_TABLE, sphere("orange", 0.3, 0.3, 0.5)]
CONE_BEHIND = [sphere("ball", 0.3, 0.1, 0.3), cone("hat", 0.3, 0.6, 0.3)]
LONE = [sphere("a", 0.0, 0.9, 0.9), sphere("b", 0.5, 0.9, 0.9)]
EPISODES = [
    # (activity, agent, others, begin)
    ("motor babbling", "Anna", ["Peter"], "2026-03-02T09:00:00+00:00"),
    ("motor babbling", "Anna", ["Peter", "HyungJin"], "2026-03-03T14:00:00+00:00"),
    ("pointing", "HyungJin", [], "2026-03-03T15:30:00+00:00"),
    ("waving", "Peter", ["Anna"], "2026-02-25T11:00:00+00:00"),
]


def live_a_week(store: Store, clock: SimulatedClock) -> tuple[SceneMemory, EpisodeMemory]:
    """The memories of the module docstring: Scene-1 two balls on a table (seen 30 times),
    Scene-2 two spheres side by side (LONE, forgotten on Tuesday), Scene-3 a ball on a table
    (the parent of Scene-1), Scene-4 a cone behind a ball, the last scene (learned: nothing
    fitted it)."""
    ensure_ontology(store)
    scenes = SceneMemory(store, clock=clock)
    episodes = EpisodeMemory(store, clock=clock)
    for activity, agent, others, begin in EPISODES:
        arguments = [ArgumentSpec("agent", agent)]
        arguments += [ArgumentSpec("partner", name) for name in others]
        episode = episodes.begin(activity, arguments=arguments, begin=begin)
        episodes.end(episode.id, end=dt.datetime.fromisoformat(begin) + dt.timedelta(minutes=20))
    for _ in range(30):
        scenes.store_scene(TWO_BALLS)
    for _ in range(5):
        scenes.retrieve(TWO_BALLS)
    scenes.store_scene(LONE)
    clock.now = START + dt.timedelta(days=1)
    for _ in range(scenes.policy.weakPassesToForget):
        scenes.sleep()
    scenes.store_scene(BALL_ON_TABLE)
    clock.now = NOW
    scenes.store_scene(CONE_BEHIND)
    return scenes, episodes


SPOKEN = (
    "when did anna last show you motor babbling",
    "when did hyungjin first do pointing",
    "how many times did anna do motor babbling",
    "how many times did peter do waving",
    "what happened yesterday afternoon",
    "what happened last week",
    "who was there when anna last did motor babbling",
    "who was there the first time peter did waving",
    "what do you know about a ball on a table",
    "what do you know about a cone behind a ball",
    "have you seen a cone behind a sphere",
    "have you seen a cup on a table",
    "what do you remember best",
    "what did you forget this week",
    "what did you forget",
    "why did you forget scene two",
    "why is scene one a kind of scene three",
    "why did you not recognise the last scene",
    "why did you learn scene three",
    "how well do you remember scene one",
    "explain scene four",
)
"""The questions of the speech tests and benchmark, as a person would say them."""


def main(argv: list[str] | None = None) -> int:
    """Write the week into a new data directory; refuse one that already holds a store."""
    parser = argparse.ArgumentParser(
        prog="python -m api.ask.samples",
        description="Write the week of Anna, HyungJin and Peter into a new data directory.",
    )
    parser.add_argument("data", type=Path, help="the data directory to create")
    data = parser.parse_args(argv).data
    if (data / "store").exists():
        print(f"{data} already holds a store; give a new directory", file=sys.stderr)
        return 2
    store = Store(data / "store")
    scenes, episodes = live_a_week(store, SimulatedClock(START))
    store.flush()
    del scenes, episodes, store
    gc.collect()  # the memories hold the store in cycles; free it before the process ends
    print(f"wrote the week of {START:%A %Y-%m-%d} into {data}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
