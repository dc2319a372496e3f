"""The scene memory's history: every event, as triples with its time, in the ``history`` graph.

Each write of :class:`reasoners.memory.SceneMemory` calls one function here with its own
transaction, so an event is committed if and only if the change it records is. An event is a
small node (a few quads, no ``rdf:type``: ``engram:eventKind`` implies
``engram:MemoryEvent``)::

    <…/history/1735689600000-1764145123456789012>
        engram:eventClass engram:Scene-4 ;     # or engram:eventScene for an experienced scene
        engram:eventKind "reinforced" ;
        prov:atTime "2025-01-01T00:00:00.000+00:00"^^xsd:dateTime ;
        engram:eventScore 1.25 ;               # the class's raw score ζ once it happened
        engram:eventLevel "LOW" ;              # its sleep level, once it has one
        engram:eventState "reinforced LOW 1.25 https://w3id.org/engram/ontology#Scene-4" .

Kinds: ``learned``, ``reinforced`` (a scene stored as the class), ``retrieved`` (the class a
cue recalled; its ancestors' counts rise too, unrecorded), ``rescored``, ``level``,
``forgotten``, ``restored``, ``pinned``, ``unpinned``. Experienced scenes get ``forgotten``,
``restored``, ``pinned`` and ``unpinned`` events.

**Compaction rule.** A sleep pass re-scores every class; recording each would add a node per
class per pass. A pass records a ``level`` event for each class whose level changed (with its
new score), and, every :data:`RESCORE_EVERY_PASSES` passes, a ``rescored`` event for each other
class whose ζ changed since the pass before. So the history grows with the updates (one event
each) and with the level changes, and by at most ``classes / RESCORE_EVERY_PASSES`` events per
pass. The score "as of T" is the score the class's last event before T recorded.

Event IRIs sort as strings in the order the events happened (the memory clock's time in ms, then
a sequence that rises across restarts), which the queries use: ``MAX(STR(?event))`` is the last.
"""

import dataclasses
import datetime as dt
import threading
import time
from collections.abc import Iterable, Mapping, Sequence

from pyoxigraph import Literal, NamedNode

from kg.store import Store
from kg.transaction import Transaction
from ontologies.vocab import (
    EVENT_BEST_MATCH,
    EVENT_CLASS,
    EVENT_CONFIDENCE,
    EVENT_KIND,
    EVENT_LEVEL,
    EVENT_PARENT,
    EVENT_SCENE,
    EVENT_SCORE,
    EVENT_STATE,
    HISTORY,
    HISTORY_NS,
    PROV_AT_TIME,
    PROV_USED,
    XSD_DATETIME,
)
from reasoners.model import ClassRecord, ItemRecord, MemoryModel
from reasoners.results import Recognition
from reasoners.scoring import WEAK

__all__ = [
    "KINDS",
    "RESCORE_EVERY_PASSES",
    "ClassState",
    "Decision",
    "Event",
    "as_of",
    "events",
    "forgetting",
    "learned_decision",
    "record",
    "record_all",
    "sleep_levels",
    "stored",
]

KINDS = (
    "learned",
    "reinforced",
    "retrieved",
    "rescored",
    "level",
    "forgotten",
    "restored",
    "pinned",
    "unpinned",
)
RESCORE_EVERY_PASSES = 10
"""Every this many sleep passes, a ``rescored`` event for each class whose ζ changed."""

_sequence_lock = threading.Lock()
_last_sequence = 0


def _next_sequence() -> int:
    """A number larger than any before it, in this process and (the wall clock permitting) in
    any process before it: the wall-clock time in ns, or one more than the last."""
    global _last_sequence
    with _sequence_lock:
        _last_sequence = max(_last_sequence + 1, time.time_ns())
        return _last_sequence


def _utc(at: dt.datetime) -> dt.datetime:
    return at.astimezone(dt.UTC)


def _time_literal(at: dt.datetime) -> Literal:
    return Literal(_utc(at).isoformat(timespec="milliseconds"), datatype=XSD_DATETIME)


def event_iri(at: dt.datetime) -> NamedNode:
    """A new event's IRI: the time in ms (13 digits) and a rising sequence (19 digits)."""
    ms = int(_utc(at).timestamp() * 1000)
    return NamedNode(f"{HISTORY_NS}{ms:013d}-{_next_sequence():019d}")


def _write(
    tx: Transaction,
    about: NamedNode,
    kind: str,
    at: dt.datetime,
    *,
    scene: bool,
    score: float | None,
    level: str | None,
) -> NamedNode:
    event = event_iri(at)
    tx.insert(event, EVENT_SCENE if scene else EVENT_CLASS, about, HISTORY)
    tx.insert(event, EVENT_KIND, Literal(kind), HISTORY)
    tx.insert(event, PROV_AT_TIME, _time_literal(at), HISTORY)
    if score is not None:
        tx.insert(event, EVENT_SCORE, Literal(float(score)), HISTORY)
    if level is not None:
        tx.insert(event, EVENT_LEVEL, Literal(level), HISTORY)
    if not scene:  # what "as of" reads, in one scan (see as_of)
        value = "-" if score is None else repr(float(score))
        state = f"{kind} {level or '-'} {value} {about.value}"
        tx.insert(event, EVENT_STATE, Literal(state), HISTORY)
    return event


def record(tx: Transaction, item: ClassRecord | ItemRecord, kind: str, at: dt.datetime) -> None:
    """Record that ``kind`` happened to a class or experienced scene at ``at``, with the score
    and level its record holds now (call it once the change is made)."""
    if isinstance(item, ClassRecord):
        _write(tx, item.iri, kind, at, scene=False, score=item.score, level=item.level)
    else:
        _write(tx, item.iri, kind, at, scene=True, score=None, level=item.level)


def stored(
    tx: Transaction,
    model: MemoryModel,
    record_: ClassRecord,
    scene: NamedNode,
    recognised: Sequence[Recognition],
    at: dt.datetime,
    learned: NamedNode | None,
) -> None:
    """Record that ``scene`` was stored as the class of ``record_`` (``learned`` is the class
    when it was learned anew, None when reinforced), with the decision as PROV: the scene the
    event used and the confidence of the best class it belonged to; for a new class, that best
    class and the parents it was placed under (a reinforced class is itself the best class)."""
    kind = "learned" if learned is not None else "reinforced"
    event = _write(tx, record_.iri, kind, at, scene=False, score=record_.score, level=record_.level)
    tx.insert(event, PROV_USED, scene, HISTORY)
    best = recognised[0] if recognised else None
    tx.insert(event, EVENT_CONFIDENCE, Literal(best.confidence if best else 0.0), HISTORY)
    if learned is not None:  # a reinforced class is itself the best match
        if best is not None:
            tx.insert(event, EVENT_BEST_MATCH, best.cls, HISTORY)
        for parent in sorted(model.parents[learned], key=str):
            tx.insert(event, EVENT_PARENT, parent, HISTORY)


def record_all(
    tx: Transaction, items: Iterable[ClassRecord | ItemRecord], kind: str, at: dt.datetime
) -> None:
    """:func:`record` for each of ``items``."""
    for item in items:
        record(tx, item, kind, at)


def forgetting(
    tx: Transaction,
    model: MemoryModel,
    classes: Sequence[NamedNode],
    items: Sequence[NamedNode],
    zetas: Mapping[NamedNode, float],
    at: dt.datetime,
) -> None:
    """Record a sleep pass's forgetting before it happens (the records are still live):
    ``classes`` with their experienced scenes, and ``items`` alone; each WEAK."""
    doomed = set(classes)
    scenes = [i for c in classes for i in model.items_of.get(c, ())]
    if doomed:  # as _forget finds them
        scenes += [i for i, r in model.items.items() if r.cls in doomed]
    for cls in classes:
        _write(tx, cls, "forgotten", at, scene=False, score=zetas.get(cls), level=WEAK)
    for item in dict.fromkeys([*scenes, *items]):
        if item in model.items:
            _write(tx, item, "forgotten", at, scene=True, score=None, level=WEAK)


def sleep_levels(
    tx: Transaction,
    model: MemoryModel,
    levels: Mapping[NamedNode, str],
    zetas: Mapping[NamedNode, float],
    at: dt.datetime,
) -> None:
    """Record a sleep pass's re-scoring under the compaction rule (module docstring). Call it
    before the pass writes the new levels and scores: the records still hold the old ones."""
    periodic = (model.sleep_passes + 1) % RESCORE_EVERY_PASSES == 0
    for cls, record_ in model.classes.items():
        level, zeta = levels[cls], zetas[cls]
        if record_.level != level:
            _write(tx, cls, "level", at, scene=False, score=zeta, level=level)
        elif periodic and record_.score != zeta:
            _write(tx, cls, "rescored", at, scene=False, score=zeta, level=level)


# Reading ---------------------------------------------------------------------------------------


@dataclasses.dataclass(frozen=True, slots=True)
class Event:
    """One event of a class's or experienced scene's history."""

    time: str
    """ISO 8601, UTC, ms precision."""
    kind: str
    score: float | None
    level: str | None

    def to_json(self) -> dict[str, object]:
        return dataclasses.asdict(self)


@dataclasses.dataclass(frozen=True, slots=True)
class ClassState:
    """A class as it was at some time: its last event then, and the score and level it left."""

    cls: NamedNode
    since: str
    """When its last event before the time happened (ISO 8601)."""
    last_event: str
    score: float | None
    level: str | None

    def to_json(self) -> dict[str, object]:
        return {
            "class": self.cls.value,
            "since": self.since,
            "last_event": self.last_event,
            "score": self.score,
            "level": self.level,
        }


def _float(term: object) -> float | None:
    return float(term.value) if isinstance(term, Literal) else None


def _text(term: object) -> str | None:
    return term.value if isinstance(term, Literal) else None


def events(store: Store, about: NamedNode) -> list[Event]:
    """The history of a class or experienced scene, oldest first (empty if it has none)."""
    rows = store.select("history_events", about=about)
    return [
        Event(
            time=_utc_text(row["time"]),
            kind=str(_text(row["kind"])),
            score=_float(row.get("score")),
            level=_text(row.get("level")),
        )
        for row in rows
    ]


@dataclasses.dataclass(frozen=True, slots=True)
class Decision:
    """What a class's ``learned`` event recorded when it was learned."""

    scene: NamedNode | None
    best: NamedNode | None
    confidence: float | None
    parents: tuple[NamedNode, ...]


def learned_decision(store: Store, cls: NamedNode) -> Decision | None:
    """The decision recorded when ``cls`` was last learned, or None (learned before Engram kept
    a history, or by ``learn_classes``, which stores no scene). A few point lookups (the
    equivalent SPARQL, ``sparql/history_decision.rq``, takes ~20 ms at 10,000 classes)."""
    learned = Literal("learned")
    events = [
        q.subject.value
        for q in store.quads(None, EVENT_CLASS, cls, HISTORY)
        if isinstance(q.subject, NamedNode)
        and any(True for _ in store.quads(q.subject, EVENT_KIND, learned, HISTORY))
    ]
    if not events:
        return None
    event = NamedNode(max(events))
    values: dict[NamedNode, list[object]] = {}
    for quad in store.quads(event, None, None, HISTORY):
        values.setdefault(quad.predicate, []).append(quad.object)
    scene = (values.get(PROV_USED) or [None])[0]
    best = (values.get(EVENT_BEST_MATCH) or [None])[0]
    parents = [p for p in values.get(EVENT_PARENT, []) if isinstance(p, NamedNode)]
    return Decision(
        scene=scene if isinstance(scene, NamedNode) else None,
        best=best if isinstance(best, NamedNode) else None,
        confidence=_float((values.get(EVENT_CONFIDENCE) or [None])[0]),
        parents=tuple(sorted(parents, key=str)),
    )


def as_of(store: Store, at: dt.datetime) -> list[ClassState]:
    """The classes that existed at ``at`` (learned or restored, not forgotten since), each with
    the score and level its last event before ``at`` left, sorted by IRI.

    The same answer as ``sparql/history_as_of.rq``, from one scan of the class events'
    ``engram:eventState`` (kind, level, score and class in one literal): an event IRI holds its
    time and sorts in event order, so the last event of each class before ``at`` is the largest
    IRI below ``<HISTORY_NS><ms of at + 1>``. (The SPARQL's grouping and join, or a lookup of
    each class's last event, take 0.5-1 s at 10,000 classes on disk.)"""
    if at.tzinfo is None:
        raise ValueError(f"at: got {at!r}, expected a timezone-aware datetime")
    bound = f"{HISTORY_NS}{int(_utc(at).timestamp() * 1000) + 1:013d}"
    last: dict[str, tuple[str, str]] = {}
    for quad in store.quads(None, EVENT_STATE, None, HISTORY):
        event, state = quad.subject.value, quad.object.value  # type: ignore[union-attr]
        if event < bound:
            cls = state.rsplit(" ", 1)[-1]
            if event > last.get(cls, ("", ""))[0]:
                last[cls] = (event, state)
    start = len(HISTORY_NS)
    states = []
    for cls, (event, state) in last.items():
        kind, level, score, _ = state.split(" ", 3)
        if kind == "forgotten":
            continue
        ms = int(event[start : start + 13])
        since = dt.datetime.fromtimestamp(ms / 1000, dt.UTC).isoformat(timespec="milliseconds")
        states.append(
            ClassState(
                cls=NamedNode(cls),
                since=since,
                last_event=kind,
                score=None if score == "-" else float(score),
                level=None if level == "-" else level,
            )
        )
    return sorted(states, key=lambda s: s.cls.value)


def _utc_text(term: object) -> str:
    text = _text(term)
    if text is None:
        raise TypeError(f"expected a time literal, got {term!r}")
    return _utc(dt.datetime.fromisoformat(text)).isoformat(timespec="milliseconds")
