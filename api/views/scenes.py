"""Stored (experienced) scenes read back from the store: lists, and one scene with its
primitives and the relations the encoder fired, as the 3D view draws them.

The triples are the ones :func:`reasoners.persist.write_item` wrote: the scene's type (its
class), creation time and episode, and per primitive its kind, label, centre, axis, radius,
height, apex and colour. Forgotten scenes are read from the trash graph the same way.
"""

import datetime as dt
from collections.abc import Sequence
from typing import Any

from pyoxigraph import Literal, NamedNode

from api.views.models import Relation, SceneDetail, SceneEntry, SceneList
from kg import Store
from kg.errors import NotFoundError
from kg.scene_triples import read_scene
from ontologies.vocab import (
    CREATED,
    ENGRAM_NS,
    EPISODIC,
    EXPERIENCED_SCENE,
    HAPPENED_DURING,
    OWL_NAMED_INDIVIDUAL,
    RDF_TYPE,
    SPATIAL_INVERSES,
    TRASH,
)

__all__ = [
    "UnknownSceneError",
    "latest_scene",
    "scene_detail",
    "scene_entries",
    "scene_list",
    "time_of",
]

_KINDS = {ENGRAM_NS + k: k for k in ("Sphere", "Cylinder", "Cone", "Plane")}
_RELATIONS = {p.value: p.value.rsplit("#", 1)[-1] for p in SPATIAL_INVERSES}


class UnknownSceneError(NotFoundError):
    """No stored scene has that name."""


def _name(iri: NamedNode) -> str:
    return iri.value.rsplit("#", 1)[-1]


def time_of(term: Any) -> dt.datetime | None:
    """The time a stored ``xsd:dateTime`` literal holds; ``None`` for anything else (no term, an
    IRI, or text that is not an ISO 8601 time), which the views show as an unknown time.

    >>> time_of(Literal("2026-01-26T08:00:00+00:00")).isoformat(), time_of(None)
    ('2026-01-26T08:00:00+00:00', None)
    """
    if not isinstance(term, Literal):
        return None
    try:
        return dt.datetime.fromisoformat(term.value)
    except ValueError:
        return None


def _entry(store: Store, item: NamedNode, graph: NamedNode) -> SceneEntry:
    created: dt.datetime | None = None
    cls: str | None = None
    episode: str | None = None
    for quad in store.quads(item, None, None, graph):
        p, o = quad.predicate, quad.object
        if p == CREATED:
            created = time_of(o)
        elif p == HAPPENED_DURING and isinstance(o, NamedNode):
            episode = o.value.rsplit("/", 1)[-1].rsplit("#", 1)[-1]
        elif p == RDF_TYPE and o not in (EXPERIENCED_SCENE, OWL_NAMED_INDIVIDUAL):
            cls = _name(o) if isinstance(o, NamedNode) else None
    return SceneEntry(
        name=_name(item),
        iri=item.value,
        cls=cls,
        created=created,
        episode=episode,
        forgotten=graph == TRASH,
    )


def scene_entries(store: Store, items: Sequence[NamedNode], graph: NamedNode) -> list[SceneEntry]:
    """The list entries of ``items``, read from ``graph``."""
    return [_entry(store, item, graph) for item in items]


def _newest_first(entries: list[SceneEntry]) -> list[SceneEntry]:
    oldest = dt.datetime.min.replace(tzinfo=dt.UTC)
    return sorted(entries, key=lambda e: (e.created or oldest, e.name), reverse=True)


def scene_list(
    store: Store, *, cls: str | None, episode: str | None, offset: int, limit: int
) -> SceneList:
    """Live stored scenes, newest first; only those of class ``cls`` or episode ``episode``
    (names) when given."""
    items = [
        q.subject
        for q in store.quads(None, RDF_TYPE, EXPERIENCED_SCENE, EPISODIC)
        if isinstance(q.subject, NamedNode)
    ]
    entries = scene_entries(store, items, EPISODIC)
    if cls is not None:
        entries = [e for e in entries if e.cls == cls]
    if episode is not None:
        entries = [e for e in entries if e.episode == episode]
    entries = _newest_first(entries)
    return SceneList(
        total=len(entries), offset=offset, limit=limit, scenes=entries[offset : offset + limit]
    )


def _graph_of(store: Store, item: NamedNode) -> NamedNode | None:
    for graph in (EPISODIC, TRASH):
        if any(True for _ in store.quads(item, RDF_TYPE, EXPERIENCED_SCENE, graph)):
            return graph
    return None


def scene_detail(store: Store, name: str) -> SceneDetail:
    """A stored scene (live or forgotten) by name or IRI, with its primitives and relations.

    Raises :class:`UnknownSceneError`."""
    try:
        item = NamedNode(name if ":" in name else ENGRAM_NS + name)
    except ValueError:
        item = None
    graph = None if item is None else _graph_of(store, item)
    if item is None or graph is None:
        raise UnknownSceneError(f"name: got {name!r}, expected the name of a stored scene")
    members = read_scene(store, item, graph)
    labels = {member.value: primitive.id for member, primitive in members}
    relations = [
        Relation(
            subject=labels[member.value],
            relation=_RELATIONS[q.predicate.value],
            object=labels[q.object.value],
        )
        for member, _ in members
        for q in store.quads(member, None, None, graph)
        if q.predicate.value in _RELATIONS
        and isinstance(q.object, NamedNode)
        and q.object.value in labels
    ]
    primitives = [primitive for _, primitive in members]
    return SceneDetail(scene=_entry(store, item, graph), primitives=primitives, relations=relations)


def latest_scene(store: Store) -> SceneDetail | None:
    """The scene stored last (by creation time), or None when none is stored."""
    page = scene_list(store, cls=None, episode=None, offset=0, limit=1)
    return scene_detail(store, page.scenes[0].iri) if page.scenes else None
