"""The memory graph: learned classes (live and forgotten) as nodes, and one class in detail.

Live classes come from :meth:`MemoryReads.classes` (scores and levels derived now); forgotten
ones from :meth:`MemoryReads.trash` and the trash graph's triples, which keep the class's
signature, counters and last score as they were when it was forgotten.
"""

import datetime as dt
import json
import threading
from dataclasses import dataclass, field
from functools import cache
from typing import Any

from pyoxigraph import Literal, NamedNode

from api.views.models import (
    ClassDetail,
    ClassNode,
    Restriction,
    SceneEntry,
    ScorePoint,
)
from api.views.scenes import scene_entries, time_of
from api.views.words import relation_of, words
from kg import Store
from kg.errors import NotFoundError
from ontologies.vocab import (
    CREATED,
    EPISODIC,
    FORGOTTEN_SIGNATURE,
    LAST_ACCESSED,
    LEVEL,
    PINNED,
    RDF_TYPE,
    RETRIEVE_COUNT,
    SCORE,
    STORE_COUNT,
    TRASH,
    TRASH_CLASS,
)
from reasoners.memory import SceneMemory
from reasoners.results import ClassSummary
from reasoners.signature import Signature

__all__ = [
    "UnknownClassError",
    "class_detail",
    "class_list_json",
    "local_name",
    "warm",
]

SCENES_SHOWN = 50
"""The stored scenes a class's detail lists, newest first."""


class UnknownClassError(NotFoundError):
    """No live or forgotten class has that name."""


def local_name(iri: NamedNode | str) -> str:
    """The part of an IRI after its ``#`` (or last ``/``)."""
    text = iri.value if isinstance(iri, NamedNode) else iri
    return text.rsplit("#", 1)[-1] if "#" in text else text.rsplit("/", 1)[-1]


def _restrictions(signature: Signature) -> list[tuple[str, str, int]]:
    return [(local_name(p), local_name(t), n) for (p, t), n in signature.items()]


@cache
def _relation(scene_property: str, target: str) -> str:
    kind, relation = relation_of(local_name(scene_property))
    return f"{kind} {relation} {local_name(target).lower()}"


def _relations(signature: Signature) -> list[str]:
    return [_relation(p.value, t.value) for (p, t) in signature]


def _live_fields(summary: ClassSummary) -> dict[str, Any]:
    """A live class as :class:`ClassNode`'s fields (plain values, so a list of 10,000 serialises
    without a model per node)."""
    return {**_node_fields(summary), "relations": _relations(summary.signature)}


def _node_fields(summary: ClassSummary) -> dict[str, Any]:
    """:func:`_live_fields` but the relations."""
    s = summary.scores
    return {
        "name": local_name(summary.iri),
        "iri": summary.iri.value,
        "complexity": summary.signature.complexity,
        "score": s.normalised,
        "level": s.level,
        "pinned": s.pinned,
        "forgotten": False,
        "items": summary.items,
        "store_count": s.store_count,
        "retrieve_count": s.retrieve_count,
        "parents": [local_name(p) for p in summary.parents],
    }


def _live_node(summary: ClassSummary) -> ClassNode:
    return ClassNode(**_live_fields(summary))


def _trash_values(store: Store, iri: NamedNode) -> dict[NamedNode, Any]:
    return {q.predicate: q.object for q in store.quads(iri, None, None, TRASH)}


def _number(term: Any, default: float = 0.0) -> float:
    try:
        return float(term.value) if isinstance(term, Literal) else default
    except ValueError:
        return default


def _forgotten_node(store: Store, iri: NamedNode, top: float) -> ClassNode | None:
    values = _trash_values(store, iri)
    if FORGOTTEN_SIGNATURE not in values:
        return None  # an experienced scene forgotten alone: not a node of the graph
    signature = Signature.from_json(values[FORGOTTEN_SIGNATURE].value)
    raw = _number(values.get(SCORE))
    return ClassNode(
        name=local_name(iri),
        iri=iri.value,
        complexity=signature.complexity,
        score=min(raw / top, 1.0) if top > 0 else 0.0,
        level="WEAK",
        pinned=values.get(PINNED, Literal(False)).value == "true",
        forgotten=True,
        items=sum(1 for _ in store.quads(None, RDF_TYPE, iri, TRASH)),
        store_count=int(_number(values.get(STORE_COUNT))),
        retrieve_count=int(_number(values.get(RETRIEVE_COUNT))),
        parents=[],
        relations=_relations(signature),
    )


def _forgotten_classes(memory: SceneMemory, top: float) -> list[ClassNode]:
    nodes = []
    for iri in memory.reads.trash():
        if any(True for _ in memory.store.quads(iri, RDF_TYPE, TRASH_CLASS, TRASH)) or any(
            True for _ in memory.store.quads(iri, FORGOTTEN_SIGNATURE, None, TRASH)
        ):
            node = _forgotten_node(memory.store, iri, top)
            if node is not None:
                nodes.append(node)
    return nodes


def _matches(node: dict[str, Any], query: str) -> bool:
    q = query.lower()
    return q in node["name"].lower() or any(q in r.lower() for r in node["relations"])


@dataclass
class _Entry:
    """One memory state's class list: nodes without their relations, the signatures (or, for
    forgotten classes, the relations) to add them from, and the pages as JSON."""

    generation: int
    nodes: list[dict[str, Any]]
    sources: list[Signature | list[str]]
    pages: dict[bool, bytes] = field(default_factory=dict)
    full: list[dict[str, Any]] | None = None

    def with_relations(self) -> list[dict[str, Any]]:
        """The nodes with their relations (derived once, when a search or a client asks)."""
        if self.full is None:
            self.full = [
                {**node, "relations": s if isinstance(s, list) else _relations(s)}
                for node, s in zip(self.nodes, self.sources, strict=True)
            ]
        return self.full

    def page(self, relations: bool) -> bytes:
        whole = self.pages.get(relations)
        if whole is None:
            shown = self.with_relations() if relations else self.nodes
            whole = self.pages[relations] = _page(shown, offset=0, limit=len(shown))
        return whole


class _NodeCache:
    """The class list of the last memory state seen (the store's transaction count names it):
    deriving 10,000 classes' scores takes a second or two, serialising them a fifth of one;
    serving them again must take neither. The graph page reads the list without relations, so
    they are derived only when a search or a client needs them; a second request for a state
    being derived waits for the first's result."""

    def __init__(self) -> None:
        self._lock = threading.Lock()
        self._computing = threading.Lock()
        self._entries: dict[tuple[int, bool], _Entry] = {}

    def get(self, memory: SceneMemory, *, trash: bool) -> _Entry:
        key, generation = (id(memory), trash), memory.store.generation
        with self._lock:
            cached = self._entries.get(key)
        if cached is not None and cached.generation == generation:
            return cached
        with self._computing:
            with self._lock:
                cached = self._entries.get(key)
            if cached is not None and cached.generation == generation:
                return cached
            summaries = memory.reads.classes()
            nodes = [_node_fields(s) for s in summaries]
            sources: list[Signature | list[str]] = [s.signature for s in summaries]
            if trash:
                top = max((s.scores.raw_score for s in summaries), default=0.0)
                for forgotten in _forgotten_classes(memory, top):
                    fields = forgotten.model_dump()
                    sources.append(fields.pop("relations"))
                    nodes.append(fields)
            entry = _Entry(generation, nodes, sources)
            with self._lock:
                self._entries = {k: v for k, v in self._entries.items() if k[0] == id(memory)}
                self._entries[key] = entry
            return entry


def warm(memory: SceneMemory) -> None:
    """Derive the class list the graph page reads first, so that its first paint after the
    server starts does not wait for it (called once the memory is loaded)."""
    _cache.get(memory, trash=False).page(relations=False)


_cache = _NodeCache()


def _without_relations(node: dict[str, Any]) -> dict[str, Any]:
    return {k: v for k, v in node.items() if k != "relations"}


def _page(nodes: list[dict[str, Any]], *, offset: int, limit: int) -> bytes:
    page: dict[str, Any] = {"total": len(nodes), "offset": offset, "limit": limit}
    page["classes"] = nodes[offset : offset + limit]
    return json.dumps(page, separators=(",", ":")).encode()


def class_list_json(
    memory: SceneMemory,
    *,
    trash: bool,
    query: str | None,
    offset: int,
    limit: int,
    relations: bool = True,
) -> bytes:
    """A :class:`ClassList` as JSON: the classes (with ``trash`` the forgotten ones too),
    simplest first, matching ``query`` (a part of the name or of a relation like
    "sphere isAboveOf plane") when given; without ``relations``, the nodes leave them out
    (a fifth of the bytes)."""
    entry = _cache.get(memory, trash=trash)
    total = len(entry.nodes)
    if not query and offset == 0 and limit >= total:
        whole = entry.page(relations)
        if limit == total:
            return whole
        return whole.replace(b'"limit":%d' % total, b'"limit":%d' % limit, 1)
    nodes = entry.with_relations()
    if query:
        nodes = [n for n in nodes if _matches(n, query)]
    if not relations:
        nodes = [_without_relations(n) for n in nodes[offset : offset + limit]]
        return _page(nodes, offset=0, limit=limit).replace(
            b'"offset":0', b'"offset":%d' % offset, 1
        )
    return _page(nodes, offset=offset, limit=limit)


def _find(memory: SceneMemory, name: str) -> tuple[ClassSummary | None, NamedNode | None]:
    for summary in memory.reads.classes():
        if local_name(summary.iri) == name or summary.iri.value == name:
            return summary, None
    for iri in memory.reads.trash():
        if local_name(iri) == name or iri.value == name:
            return None, iri
    raise UnknownClassError(
        f"name: got {name!r}, expected the name of a learned or forgotten scene class"
    )


def _history(memory: SceneMemory, iri: NamedNode, node: ClassNode) -> list[ScorePoint]:
    """Past scores when the memory keeps them (a ``score_history`` method returning records
    with ``time``, ``normalised`` and ``level``), then the score now."""
    points: list[ScorePoint] = []
    history = getattr(memory, "score_history", None)
    if callable(history):
        for record in history(iri):
            points.append(
                ScorePoint(
                    time=record.time,
                    score=record.normalised,
                    level=getattr(record, "level", None),
                )
            )
    points.append(ScorePoint(time=dt.datetime.now(dt.UTC), score=node.score, level=node.level))
    return points


def _scenes_of(store: Store, iri: NamedNode, graph: NamedNode) -> list[SceneEntry]:
    items = [q.subject for q in store.quads(None, RDF_TYPE, iri, graph)]
    entries = scene_entries(store, [i for i in items if isinstance(i, NamedNode)], graph)
    entries.sort(key=lambda e: e.created or dt.datetime.min.replace(tzinfo=dt.UTC), reverse=True)
    return entries[:SCENES_SHOWN]


def class_detail(memory: SceneMemory, name: str) -> ClassDetail:
    """One class (live or forgotten) by its name or IRI; raises :class:`UnknownClassError`."""
    summary, trashed = _find(memory, name)
    if summary is not None:
        node, s = _live_node(summary), summary.scores
        restrictions = _restrictions(summary.signature)
        return ClassDetail(
            node=node,
            words=words(restrictions),
            restrictions=[Restriction(property=p, type=t, n=n) for p, t, n in restrictions],
            children=[local_name(c) for c in summary.children],
            raw_score=s.raw_score,
            stored_level=s.stored_level,
            consecutive_weak=s.consecutive_weak,
            created=s.created,
            last_accessed=s.last_accessed,
            history=_history(memory, summary.iri, node),
            scenes=_scenes_of(memory.store, summary.iri, EPISODIC),
        )
    assert trashed is not None
    top = max((c.scores.raw_score for c in memory.reads.classes()), default=0.0)
    forgotten = _forgotten_node(memory.store, trashed, top)
    if forgotten is None:
        raise UnknownClassError(f"name: {name!r} is a forgotten scene, not a class")
    values = _trash_values(memory.store, trashed)
    signature = Signature.from_json(values[FORGOTTEN_SIGNATURE].value)
    restrictions = _restrictions(signature)
    level = values.get(LEVEL)
    return ClassDetail(
        node=forgotten,
        words=words(restrictions),
        restrictions=[Restriction(property=p, type=t, n=n) for p, t, n in restrictions],
        children=[],
        raw_score=_number(values.get(SCORE)),
        stored_level=level.value if isinstance(level, Literal) else None,
        consecutive_weak=None,
        created=time_of(values.get(CREATED)),
        last_accessed=time_of(values.get(LAST_ACCESSED)),
        history=[],
        scenes=_scenes_of(memory.store, trashed, TRASH),
    )
