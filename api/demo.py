"""The main job: a scripted memory life on the embedded store, from point clouds to forgetting.

A simulated clock runs through three days. Synthetic tabletop point clouds (``shapes.synthetic``)
go through perception (segment, fit, track, average) into the directive API in this process
(LOAD INIT … SCENE UPDATED, one transaction per scene), inside an autobiographical episode. Some
scenes come back often, some once; partial cues are recalled; sleep passes consolidate and
forget. Everything printed is read back from the memory, nothing is made up by the script.
"""

import datetime as dt
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import httpx
import numpy as np
from pyoxigraph import NamedNode
from rich.console import Console
from rich.table import Table

from api.armor import ArmorEngine
from api.ask import Asker
from api.ask.dialogue import questions_for, talk
from api.client import ArmorClient, LocalTransport
from api.perceive import perceive
from episodes import ArgumentSpec, Cue, EpisodeMemory
from kg import Store
from kg.clock import SimulatedClock
from kg.export import export
from reasoners.memory import SceneMemory
from reasoners.results import ItemScores
from shapes import Frame, Perception
from shapes.synthetic import PALETTE, SyntheticShot, TabletopScene, TruthObject

__all__ = ["SCENES", "run_demo"]

START = dt.datetime(2026, 1, 26, 8, 0, tzinfo=dt.UTC)
FRAMES_PER_VIEW = 8


def _sphere(x: float, y: float, r: float, colour: str) -> TruthObject:
    return TruthObject("Sphere", (x, y, 0.0), radius=r, height=2 * r, colour=PALETTE[colour])


def _can(x: float, y: float, r: float, h: float, colour: str) -> TruthObject:
    return TruthObject("Cylinder", (x, y, 0.0), radius=r, height=h, colour=PALETTE[colour])


def _cone(x: float, y: float, r: float, h: float, colour: str) -> TruthObject:
    return TruthObject("Cone", (x, y, 0.0), radius=r, height=h, colour=PALETTE[colour])


SCENES: dict[str, TabletopScene] = {
    "breakfast": TabletopScene(
        (_sphere(-0.18, 0.0, 0.04, "yellow"), _can(0.12, 0.0, 0.04, 0.14, "blue"))
    ),
    "breakfast and a funnel": TabletopScene(
        (
            _sphere(-0.18, 0.0, 0.04, "yellow"),
            _can(0.12, 0.0, 0.04, 0.14, "blue"),
            _cone(0.0, 0.2, 0.05, 0.12, "red"),
        )
    ),
    "two cans": TabletopScene(
        (_can(-0.15, 0.1, 0.035, 0.12, "green"), _can(0.15, -0.05, 0.04, 0.18, "pink"))
    ),
    "a ball alone": TabletopScene((_sphere(0.0, 0.0, 0.06, "red"),)),
}
"""The tabletop scenes the robot sees (x right, y away from the camera, z up; metres)."""

SCRIPT: tuple[tuple[float, str], ...] = (
    (0.0, "breakfast"),
    (0.2, "breakfast and a funnel"),
    (0.4, "two cans"),
    (0.6, "breakfast"),
    (0.8, "a ball alone"),
    (1.0, "breakfast"),
    (1.5, "breakfast and a funnel"),
    (2.0, "breakfast"),
    (3.0, "breakfast"),
    (4.0, "breakfast"),
    (5.0, "breakfast"),
    (6.0, "breakfast"),
    (7.0, "breakfast"),
    (8.0, "breakfast"),
    (9.0, "breakfast"),
    (10.0, "breakfast"),
)
"""(hours after the start of day one, scene): what the robot sees, in order. Breakfast is a
routine; a ball alone on the table is seen once and never asked about, so it fades."""

CUES: tuple[tuple[str, list[str]], ...] = (
    ("a ball to the left of a can", ["Sphere isLeftOf Cylinder"]),
    ("a cone behind a can", ["Cone isBehindOf Cylinder"]),
    ("a can to the left of another", ["Cylinder isLeftOf Cylinder"]),
)


@dataclass
class Demo:
    """What the demo works with: the store, its memories, and the console it prints to."""

    store: Store
    memory: SceneMemory
    episodes: EpisodeMemory
    client: ArmorClient
    clock: SimulatedClock
    console: Console

    def name(self, iri: NamedNode | str) -> str:
        text = iri.value if isinstance(iri, NamedNode) else iri.strip("<>")
        return text.rsplit("#", 1)[-1]

    def definition(self, iri: NamedNode) -> str:
        return " ⊓ ".join(
            f"({self.name(p)} ≥{n} {self.name(t)})"
            for (p, t), n in self.memory.reads.signature(iri).items()
        )


FRAME_NS = 100_000_000
"""The camera's frame period in the simulated time (10 Hz)."""


def _record(recorder: Any, shot: SyntheticShot, time_ns: int) -> None:
    """One frame into the episode's streams: the camera image (a quarter of its size, for the
    Episodes page's frames and replay) and, to plot, the share of pixels with a depth and
    their median depth."""
    image = np.asarray(np.clip(shot.rgb[::4, ::4] * 255, 0, 255), dtype=np.uint8)
    seen = np.isfinite(shot.depth)
    depth = float(np.median(shot.depth[seen])) if seen.any() else 0.0
    recorder.tick(
        {"camera/rgb": image, "camera/depth": np.array([seen.mean(), depth])}, time_ns=time_ns
    )


def _frames(scene: TabletopScene, seed: int, recorder: Any, start: dt.datetime) -> Iterator[Frame]:
    """The frames of one view of ``scene``, then of the cleared table, each recorded."""
    rng = np.random.default_rng(seed)
    empty = TabletopScene(())
    views = [scene] * FRAMES_PER_VIEW + [empty] * 4  # cleared: the next scene starts fresh
    start_ns = int(start.timestamp() * 1e9)
    for index, view in enumerate(views):
        shot = view.render(rng)
        _record(recorder, shot, start_ns + index * FRAME_NS)
        yield shot.frame


def _see(demo: Demo, perception: Perception, episode_iri: str, recorder: Any) -> None:
    table = Table(title="Perceived and stored (one transaction per scene)", title_justify="left")
    for column in ("time", "scene", "primitives", "outcome", "class", "confidence"):
        table.add_column(column)
    for index, (hours, title) in enumerate(SCRIPT):
        demo.clock.now = START + dt.timedelta(hours=hours)
        for result in perceive(
            _frames(SCENES[title], index, recorder, demo.clock.now),
            demo.client,
            perception=perception,
            episode=episode_iri,
        ):
            kinds = ", ".join(sorted(p.kind.value for p in result.scene.primitives))
            table.add_row(
                demo.clock.now.strftime("%a %H:%M"),
                title,
                kinds,
                "learned" if result.learned else "recognised",
                demo.name(result.stored_as),
                result.answer.details.get("confidence", ["?"])[0],
            )
    demo.console.print(table)


def _print_classes(demo: Demo, title: str) -> None:
    table = Table(title=title, title_justify="left")
    for column in ("class", "d", "s", "r", "score", "level", "parents"):
        table.add_column(column)
    for summary in sorted(demo.memory.reads.classes(), key=lambda c: c.iri.value):
        scores: ItemScores = summary.scores
        table.add_row(
            demo.name(summary.iri),
            str(scores.complexity),
            str(scores.store_count),
            str(scores.retrieve_count),
            f"{scores.normalised:.2f}",
            scores.level + (" (pinned)" if scores.pinned else ""),
            ", ".join(demo.name(p) for p in summary.parents) or "Scene",
        )
    demo.console.print(table)


def _recall(demo: Demo) -> None:
    table = Table(title="Recalled from partial cues (never written)", title_justify="left")
    for column in ("cue", "recalled", "generalisations", "similar"):
        table.add_column(column)
    for words, cue in CUES:
        answer = demo.client.memory.retrieve(cue)
        details = answer.details
        table.add_row(
            words,
            demo.name(answer.values[0]) if answer.values else "nothing",
            ", ".join(demo.name(g.split()[0]) for g in details.get("generalisation", [])) or "-",
            ", ".join(
                f"{demo.name(s.split()[0])} {float(s.split()[1]):.2f}"
                for s in details.get("similar", [])[:3]
            )
            or "-",
        )
    demo.console.print(table)


def _ranked(demo: Demo, pairs: list[str]) -> list[str]:
    """ "<class> <similarity>" details as short names with two decimals."""
    return [f"{demo.name(c)} {float(v):.2f}" for c, v in (pair.split() for pair in pairs)]


def _sleep_days(demo: Demo, days: int) -> None:
    table = Table(title="Nights pass: sleep passes consolidate and forget", title_justify="left")
    for column in ("time", "rescored", "WEAK classes", "forgotten classes", "forgotten items"):
        table.add_column(column)
    for _ in range(days):
        demo.clock.advance(hours=12)
        report = demo.memory.sleep()
        weak = sorted(demo.name(c) for c, level in report.levels.items() if level == "WEAK")
        table.add_row(
            demo.clock.now.strftime("%a %H:%M"),
            str(report.rescored),
            ", ".join(weak) or "-",
            ", ".join(demo.name(c) for c in report.forgotten_classes) or "-",
            str(len(report.forgotten_items)),
        )
    demo.console.print(table)


def run_demo(store: Store, data_dir: Path, console: Console) -> Path:
    """Live through the script on ``store``; return the path of the OWL export for Protégé."""
    clock = SimulatedClock(START)
    memory = SceneMemory(store, clock=clock)
    engine = ArmorEngine(store, scene_memory=memory)
    http = httpx.Client(base_url="http://engram.local", transport=LocalTransport(engine))
    demo = Demo(
        store,
        memory,
        EpisodeMemory(store, data_dir=data_dir, clock=clock),
        ArmorClient("demo-camera", "engram", http=http),
        clock,
        console,
    )
    console.rule("Day one: the robot watches the table")
    episode = demo.episodes.begin(
        "tidying",
        activity_type="demonstration",
        arguments=[ArgumentSpec("agent", "HyungJin"), ArgumentSpec("object", "table")],
        record=True,
    )
    recorder = demo.episodes.streams.recordings.get(episode.id)
    recorder.add_provider("camera/rgb", "image", encoding="rgb8")
    recorder.add_provider("camera/depth", "float_array", dtype="float64", shape=[2])
    _see(demo, Perception(seed=0), episode.iri, recorder)
    demo.episodes.end(episode.id)
    for summary in sorted(memory.reads.classes(), key=lambda c: c.iri.value):
        console.print(f"[bold]{demo.name(summary.iri)}[/bold] ≡ {demo.definition(summary.iri)}")
    _print_classes(demo, "What was learned (scores and levels derived from the raw terms)")
    _recall(demo)
    console.rule("Days pass")
    _sleep_days(demo, 6)
    _print_classes(demo, "What the memory holds after the nights")
    trash = memory.reads.trash()
    console.print(f"In the trash: {', '.join(demo.name(t) for t in trash) or 'nothing'}")
    if trash:  # forgotten classes come first
        restored = memory.restore(trash[0])
        names = ", ".join(demo.name(r) for r in restored)
        console.print(f"Restored from the trash on request: {names}")
        memory.pin(restored[0])
        console.print(f"Pinned, so never forgotten again: {demo.name(restored[0])}")
    recollection = demo.episodes.recall(Cue("tidying", agent="HyungJin"))
    console.print(
        f"'When did HyungJin last show you tidying?' — {recollection.when} "
        f"(episode {recollection.episode.id})"
    )
    target = data_dir / "engram.owl"
    body = export(store, ["tbox", "memory"], "rdfxml")
    partial = target.with_name(target.name + ".part")
    partial.write_bytes(body)
    partial.replace(target)
    console.print(f"OWL export for Protégé: [bold]{target}[/bold] ({len(body):,} bytes)")
    console.rule("Asking the memory in words")
    asker = Asker(memory, demo.episodes)
    talk(asker, questions_for(asker, agent="HyungJin", activity="tidying"), console)
    return target
