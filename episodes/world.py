"""The world at an episode's begin and end: what was on the table, and who was there.

When an episode begins or ends, its memory snapshot (``engram:stateAtBegin`` /
``engram:stateAtEnd``) links the scene memory's current scene, the experienced scene stored
last (``engram:sceneAtTime``: its primitives with their attributes and relations, and the class
it was stored as, stay in the ``episodic`` graph, or in ``trash`` once forgotten), and the
participants of the episode's arguments then (``engram:participantAtTime``). "What was on the
table when HyungJin started babbling?" is then one SPARQL query (see the README), and
:func:`world_change` tells what appeared, disappeared and stayed between begin and end.
"""

from collections.abc import Iterable
from dataclasses import dataclass

from pyoxigraph import Literal, NamedNode

from episodes import _rdf
from episodes.errors import InvalidInputError
from episodes.terms import episode_iri
from kg import Store, Transaction
from ontologies.vocab import ENGRAM_NS, EPISODES, PARTICIPANT_AT_TIME, SCENE_AT_TIME

__all__ = [
    "WorldChange",
    "WorldObject",
    "WorldState",
    "current_scene",
    "world_at",
    "world_change",
    "write_world",
]


@dataclass(frozen=True)
class WorldObject:
    """A primitive of the scene then: its label (tracking id), kind and IRI."""

    label: str
    kind: str
    iri: str


@dataclass(frozen=True)
class WorldState:
    """The current scene at one moment of an episode (``None`` before any scene was stored),
    the class it was stored as, its primitives, and the participants then."""

    scene: str | None
    scene_class: str | None
    objects: tuple[WorldObject, ...]
    participants: tuple[str, ...]


@dataclass(frozen=True)
class WorldChange:
    """The world at begin and end of an episode, and the difference (objects by label and
    kind; participants by name)."""

    begin: WorldState | None
    end: WorldState | None
    appeared: tuple[WorldObject, ...]
    disappeared: tuple[WorldObject, ...]
    stayed: tuple[WorldObject, ...]
    joined: tuple[str, ...]
    left: tuple[str, ...]


def current_scene(store: Store) -> NamedNode | None:
    """The experienced scene the scene memory stored last, or ``None``."""
    rows = store.select("episodes_current_scene")
    return _rdf.iri(rows[0], "scene") if rows else None


def write_world(
    tx: Transaction, state: NamedNode, scene: NamedNode | None, participants: Iterable[NamedNode]
) -> None:
    """Link the snapshot ``state`` to the current scene and the participants then."""
    if scene is not None:
        tx.insert(state, SCENE_AT_TIME, scene, EPISODES)
    for who in participants:
        tx.insert(state, PARTICIPANT_AT_TIME, who, EPISODES)


def _short(iri: str) -> str:
    return iri.removeprefix(ENGRAM_NS)


def world_at(store: Store, episode_id: str, moment: str) -> WorldState | None:
    """The world at ``moment`` (``"begin"`` or ``"end"``) of an episode; ``None`` when no
    snapshot was taken then (not ended yet, or imported)."""
    if moment not in ("begin", "end"):
        raise InvalidInputError("moment", moment, "'begin' or 'end'")
    rows = store.select("episodes_world", episode=episode_iri(episode_id), moment=Literal(moment))
    if not rows:
        return None
    objects = tuple(
        WorldObject(
            label=_rdf.opt_text(r, "label") or _rdf.text(r, "object"),
            kind=_short(_rdf.text(r, "kind")),
            iri=_rdf.text(r, "object"),
        )
        for r in rows
        if "object" in r
    )
    first = rows[0]
    return WorldState(
        scene=_rdf.opt_text(first, "scene"),
        scene_class=_rdf.opt_text(first, "cls"),
        objects=objects,
        participants=_rdf.names(first),
    )


def world_change(store: Store, episode_id: str) -> WorldChange:
    """The world at begin and end of an episode and what changed between them."""
    before = world_at(store, episode_id, "begin")
    after = world_at(store, episode_id, "end")
    old = {(o.label, o.kind): o for o in before.objects} if before else {}
    new = {(o.label, o.kind): o for o in after.objects} if after else {}
    people_before = set(before.participants) if before else set()
    people_after = set(after.participants) if after else set()
    return WorldChange(
        begin=before,
        end=after,
        appeared=tuple(new[k] for k in sorted(new.keys() - old.keys())),
        disappeared=tuple(old[k] for k in sorted(old.keys() - new.keys())),
        stayed=tuple(new[k] for k in sorted(new.keys() & old.keys())),
        joined=tuple(sorted(people_after - people_before)),
        left=tuple(sorted(people_before - people_after)),
    )
