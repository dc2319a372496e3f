"""A follower's scene memory, updated piecewise from the journal, equals one rebuilt from the
store: after learning, reinforcing, retrieving, pinning and a sleep pass."""

import datetime as dt
import random

import pytest

from kg.fleet import open_remote
from kg.follow import Follower
from kg.primitive import Primitive
from reasoners.follow import apply_change
from reasoners.memory import SceneMemory

pytestmark = pytest.mark.slow

CLOCK = dt.datetime(2026, 1, 1, tzinfo=dt.UTC)


def _scene(rng: random.Random, count: int) -> list[Primitive]:
    kinds = ["Sphere", "Cylinder", "Cone", "Plane"]
    scene = []
    for k in range(count):
        kind = rng.choice(kinds)
        centre = (rng.uniform(0, 1), rng.uniform(0, 1), rng.uniform(0, 0.5))
        if kind == "Sphere":
            scene.append(Primitive(f"o{k}", kind, centre=centre, radius=0.04))
        else:
            scene.append(Primitive(f"o{k}", kind, centre=centre, axis=(0.0, 0.0, 1.0)))
    return scene


def _view(memory: SceneMemory) -> object:
    return (
        [(c.iri, c.parents, c.children, c.scores) for c in memory.reads.classes()],
        {i: memory.reads.item_scores(i) for i in memory.reads.items()},
        memory.reads.state(),
    )


def test_piecewise_updates_match_a_rebuild(
    sparql_server: tuple[str, str], memory_name: str
) -> None:
    url, profile = sparql_server
    writer = open_remote(url, memory_name, profile=profile)
    reader = open_remote(url, memory_name, profile=profile, follow=True, poll_s=3600)
    try:
        memory = SceneMemory(writer.store, clock=lambda: CLOCK)
        mirror = SceneMemory(reader.store, clock=lambda: CLOCK)
        follower = Follower(reader.dataset)
        outcomes: list[bool] = []
        reader.dataset.listen(lambda change: outcomes.append(apply_change(mirror, change.touched)))
        follower.catch_up()  # the writer loaded the T-box: too large to list, a rebuild
        assert outcomes == [False]
        outcomes.clear()
        rng = random.Random(5)
        scenes = [_scene(rng, rng.randint(2, 4)) for _ in range(6)]
        for scene in [*scenes, scenes[0], scenes[2]]:
            memory.store_scene(scene)
            follower.catch_up()
        memory.retrieve([("Sphere", "isAboveOf", "Plane")])
        follower.catch_up()
        first = memory.reads.classes()[0].iri
        memory.pin(first)
        follower.catch_up()
        assert outcomes and all(outcomes)  # every one of these applied piecewise
        rebuilt = SceneMemory(reader.store, clock=lambda: CLOCK)
        assert _view(mirror) == _view(rebuilt) == _view(memory)
        # one transaction learning 600 classes: listed in the journal, applied piecewise
        outcomes.clear()
        batch = [memory.encoder.signature(_scene(rng, rng.randint(2, 5))) for _ in range(700)]
        learned = memory.learn_classes([s for s in batch if s][:600])
        follower.catch_up()
        assert len(learned) > 500 and outcomes == [True]
        assert _view(mirror) == _view(memory)
        memory.sleep()
        follower.catch_up()
        assert _view(mirror) == _view(memory)
    finally:
        reader.close()
        writer.close()
