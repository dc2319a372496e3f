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
        engram:eventLevel "LOW" .              # its sleep level, once it has one
    <…/history/epoch-3>                        # the journal of the current epoch (below)
        engram:historyEntry "1735689600000-1764145123456789012 reinforced LOW 1.25 …#Scene-4" .

Kinds: ``learned``, ``reinforced`` (a scene stored as the class), ``retrieved`` (the class a
cue recalled; its ancestors' counts rise too, unrecorded), ``rescored``, ``level``,
``forgotten``, ``restored``, ``pinned``, ``unpinned``. Experienced scenes get ``forgotten``,
``restored``, ``pinned`` and ``unpinned`` events.

**Compaction rule.** A sleep pass re-scores every class; recording each would add a node per
class per pass. A pass records a ``level`` event for each class whose level changed (with its
new score), and, every :data:`RESCORE_EVERY_PASSES` passes, a ``rescored`` event for each other
class whose ζ changed since the last update or pass that scored it. These events of one pass
are not nodes: they are lines of one plain-text literal per pass, ``engram:historyPassEvents``
on the epoch node (:func:`sleep_levels`; layout: :data:`~ontologies.vocab.HISTORY_PASS_EVENTS`),
so a pass that changes the level of every class writes one quad. :func:`as_of` and
:func:`events` read them as they read the other events, and ``sparql/history_as_of.rq`` reads
them with SPARQL's string functions. The score "as of T" is the score the class's last event
before T recorded.

Event IRIs sort as strings in the order the events happened (the memory clock's time in ms, then
a sequence that rises across restarts), which the queries use: ``MAX(STR(?event))`` is the last.

**Checkpoints (as of T).** An event about a class also adds one line to the journal of the
current epoch: ``engram:historyEntry`` on ``<…/history/epoch-k>``, the event's IRI tail, kind,
level, score and class in one literal, which one lookup of the epoch node reads back. (Histories
written before checkpoints kept that line, without the IRI, as ``engram:eventState`` on the
event.) At the end of a sleep pass, once epoch k holds at least :data:`CHECKPOINT_MIN_EVENTS`
class events and a quarter as many as there are live classes (or at the first pass of a history
from before checkpoints), the pass writes, in its transaction, checkpoint k+1
(``<…/history/checkpoint-k+1>``): each class's last event among all those written so far
(``engram:checkpointState``, journal lines, zlib + base64; forgotten classes included) and a
summary (``engram:checkpointSummary``: its number, the largest event it covers and the smallest
event of epoch k), and epoch k+1 begins. The memory reads the current epoch (the last
checkpoint's number) from the store once per model (``ModelState.history_epoch``), so it
survives restarts and a rebuilt model. :func:`as_of` takes the latest checkpoint covering only
events before T, and folds in the journal of its epoch and of each later epoch that holds an
event before T (with a clock that only moves forward: the current one); with no such
checkpoint, the full scan of every class event (``bench/history.py`` measures both).

**Growth.** The journal line replaces the ``eventState`` quad (the same quads per event, ~33
bytes more). A sleep pass adds one literal (a line of about 80 bytes per event), none when
nothing changed. A checkpoint costs ~24 bytes per class (zlib level 1: 100,000 lines
compress in a quarter of the time level 6 takes, for ~20 bytes a class), and comes only after
at least ``max(1000, classes / 4)`` class events.
"""

import base64
import dataclasses
import datetime as dt
import threading
import time
import zlib
from collections.abc import Iterable, Iterator, Mapping, Sequence

from pyoxigraph import Literal, NamedNode, Quad

from kg.store import Store
from kg.transaction import QuadReader, Transaction
from ontologies.vocab import (
    CHECKPOINT_STATE,
    CHECKPOINT_SUMMARY,
    EVENT_BEST_MATCH,
    EVENT_CLASS,
    EVENT_CONFIDENCE,
    EVENT_KIND,
    EVENT_LEVEL,
    EVENT_PARENT,
    EVENT_PARENTS,
    EVENT_SCENE,
    EVENT_SCORE,
    EVENT_STATE,
    HISTORY,
    HISTORY_ENTRY,
    HISTORY_NS,
    HISTORY_PASS_ENTRIES,
    HISTORY_PASS_EVENTS,
    PROV_AT_TIME,
    PROV_USED,
    XSD_DATETIME,
)
from reasoners.batch import matches
from reasoners.model import MemoryModel
from reasoners.records import ClassRecord, ItemRecord
from reasoners.results import Recognition
from reasoners.scoring import WEAK

__all__ = [
    "CHECKPOINT_MIN_EVENTS",
    "KINDS",
    "RESCORE_EVERY_PASSES",
    "ClassState",
    "Decision",
    "Event",
    "as_of",
    "checkpoint",
    "current_epoch",
    "events",
    "forgetting",
    "learned_decision",
    "pass_entries",
    "pass_text",
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
CHECKPOINT_MIN_EVENTS = 1_000
"""A sleep pass writes a checkpoint once the epoch holds this many class events and at least a
quarter as many as there are live classes (see :func:`checkpoint`)."""
_NONE = "~"
"""Sorts after every event IRI's tail: "no event"."""

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


def _epoch_node(epoch: int) -> NamedNode:
    return NamedNode(f"{HISTORY_NS}epoch-{epoch}")


def _checkpoint_node(number: int) -> NamedNode:
    return NamedNode(f"{HISTORY_NS}checkpoint-{number}")


def _epoch(model: MemoryModel) -> int:
    if model.state.history_epoch is None:
        raise RuntimeError("history: the model's history epoch was not read (current_epoch)")
    return model.state.history_epoch


def _write(
    tx: Transaction,
    model: MemoryModel,
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
    if not scene:  # what "as of" reads: the epoch's journal (see as_of)
        entry = _entry(event.value[len(HISTORY_NS) :], kind, level, score, about)
        tx.insert(_epoch_node(_epoch(model)), HISTORY_ENTRY, Literal(entry), HISTORY)
    return event


def _entry(event: str, kind: str, level: str | None, score: float | None, about: NamedNode) -> str:
    value = "-" if score is None else repr(float(score))
    return f"{event} {kind} {level or '-'} {value} {about.value}"


def _unpack(term: object) -> list[str]:
    """The journal lines of a packed pass literal of an older history (zlib + base64)."""
    text = zlib.decompress(base64.b64decode(term.value)).decode()  # type: ignore[attr-defined]
    return text.split("\n") if text else []


def record(
    tx: Transaction,
    model: MemoryModel,
    item: ClassRecord | ItemRecord,
    kind: str,
    at: dt.datetime,
) -> None:
    """Record that ``kind`` happened to a class or experienced scene at ``at``, with its ζ as
    of its last update or sleep pass and the level of its last pass (call it once the change
    is made)."""
    if isinstance(item, ClassRecord):
        score = model.scores.scored.get(item.iri, item.score)
        _write(tx, model, item.iri, kind, at, scene=False, score=score, level=item.level)
    else:
        _write(tx, model, item.iri, kind, at, scene=True, score=None, level=item.level)


def stored(
    tx: Transaction,
    model: MemoryModel,
    record_: ClassRecord,
    scene: NamedNode,
    best: Recognition | None,
    at: dt.datetime,
    learned: NamedNode | None,
) -> None:
    """Record that ``scene`` was stored as the class of ``record_`` (``learned`` is the class
    when it was learned anew, None when reinforced), with the decision as PROV: the scene the
    event used and the confidence of ``best``, the best class it belonged to (None: none); for
    a new class, that best class and the parents it was placed under (a reinforced class is
    itself the best class)."""
    kind = "learned" if learned is not None else "reinforced"
    event = _write(
        tx, model, record_.iri, kind, at, scene=False, score=record_.score, level=record_.level
    )
    tx.insert(event, PROV_USED, scene, HISTORY)
    tx.insert(event, EVENT_CONFIDENCE, Literal(best.confidence if best else 0.0), HISTORY)
    if learned is not None:  # a reinforced class is itself the best match
        if best is not None:
            tx.insert(event, EVENT_BEST_MATCH, best.cls, HISTORY)
        parents = " ".join(sorted(parent.value for parent in model.graph.parents[learned]))
        tx.insert(event, EVENT_PARENTS, Literal(parents), HISTORY)


def record_all(
    tx: Transaction,
    model: MemoryModel,
    items: Iterable[ClassRecord | ItemRecord],
    kind: str,
    at: dt.datetime,
) -> None:
    """:func:`record` for each of ``items``."""
    for item in items:
        record(tx, model, item, kind, at)


def forgetting(
    tx: Transaction,
    model: MemoryModel,
    classes: Sequence[NamedNode],
    items: Sequence[NamedNode],
    zetas: Mapping[NamedNode, float],
    at: dt.datetime,
) -> None:
    """Record a sleep pass's forgetting before it happens (the records are still live, with
    the level this pass gave them): ``classes`` (WEAK) and ``items``, every experienced scene
    that leaves with them or alone (reasoners.forgetting.leaving_items)."""
    for cls in classes:
        _write(tx, model, cls, "forgotten", at, scene=False, score=zetas.get(cls), level=WEAK)
    for item in items:
        level = model.items.records[item].level
        _write(tx, model, item, "forgotten", at, scene=True, score=None, level=level)


def sleep_levels(
    tx: Transaction,
    model: MemoryModel,
    levels: Mapping[NamedNode, str],
    zetas: Mapping[NamedNode, float],
    at: dt.datetime,
) -> int:
    """Record a sleep pass's re-scoring under the compaction rule (module docstring), as one
    ``engram:historyPassEntries`` literal; return the number of events it holds (none: nothing
    written). Call it before the pass sets the new levels: the records still hold the old ones.
    """
    periodic = (model.state.sleep_passes + 1) % RESCORE_EVERY_PASSES == 0
    scored = model.scores.scored
    lines = []
    for cls, record_ in model.graph.classes.items():
        level, zeta = levels[cls], zetas[cls]
        if record_.level != level:
            lines.append(f"{cls.value} level {level} {float(zeta)!r}\n")
        elif periodic and scored.get(cls, record_.score) != zeta:
            lines.append(f"{cls.value} rescored {level} {float(zeta)!r}\n")
    if lines:
        event = event_iri(at).value[len(HISTORY_NS) :]
        head = f"{event} {_time_literal(at).value}\n"
        text = Literal(head + "".join(lines))
        tx.insert(_epoch_node(_epoch(model)), HISTORY_PASS_EVENTS, text, HISTORY)
    return len(lines)


def pass_entries(term: object) -> list[str]:
    """The journal entries ("<event> <kind> <level> <score> <class IRI>") of one pass's
    :data:`~ontologies.vocab.HISTORY_PASS_EVENTS` text."""
    text = term.value  # type: ignore[attr-defined]
    head, _, body = text.partition("\n")
    event = head.partition(" ")[0]
    entries = []
    for line in body.split("\n"):
        if line:
            cls, kind, level, score = line.split(" ")
            entries.append(f"{event} {kind} {level} {score} {cls}")
    return entries


def pass_text(entries: Sequence[str]) -> Literal:
    """The :data:`~ontologies.vocab.HISTORY_PASS_EVENTS` text of one pass's journal entries
    (all of one event), as :func:`sleep_levels` writes it (a migration rewrites a history's
    older packed pass literals with it)."""
    event = entries[0].partition(" ")[0]
    moment = dt.datetime.fromtimestamp(int(event[:13]) / 1000, dt.UTC)
    lines = [f"{event} {_time_literal(moment).value}\n"]
    for entry in entries:
        _, kind, level, score, cls = entry.split(" ")
        lines.append(f"{cls} {kind} {level} {score}\n")
    return Literal("".join(lines))


def _passes(reader: QuadReader, node: NamedNode | None) -> Iterator[str]:
    """The journal entries of the sleep passes recorded on epoch ``node`` (every epoch with
    None), in either layout."""
    for quad in reader.quads(node, HISTORY_PASS_EVENTS, None, HISTORY):
        yield from pass_entries(quad.object)
    for quad in reader.quads(node, HISTORY_PASS_ENTRIES, None, HISTORY):
        yield from _unpack(quad.object)


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
    """The history of a class or experienced scene, oldest first (empty if it has none): its
    event nodes and the sleep passes' events about it."""
    start = len(HISTORY_NS)
    found = [
        (
            row["event"].value[start:],
            Event(
                time=_utc_text(row["time"]),
                kind=str(_text(row["kind"])),
                score=_float(row.get("score")),
                level=_text(row.get("level")),
            ),
        )
        for row in store.select("history_events", about=about)
    ]
    suffix = f" {about.value}"
    for entry in _passes(store, None):
        if entry.endswith(suffix):
            event, kind, level, score, _ = entry.split(" ", 4)
            time_ = dt.datetime.fromtimestamp(int(event[:13]) / 1000, dt.UTC)
            found.append(
                (
                    event,
                    Event(
                        time=time_.isoformat(timespec="milliseconds"),
                        kind=kind,
                        score=None if score == "-" else float(score),
                        level=None if level == "-" else level,
                    ),
                )
            )
    return [e for _, e in sorted(found, key=lambda pair: pair[0])]


@dataclasses.dataclass(frozen=True, slots=True)
class Decision:
    """What a class's ``learned`` event recorded when it was learned."""

    scene: NamedNode | None
    best: NamedNode | None
    confidence: float | None
    parents: tuple[NamedNode, ...]


def learned_decision(store: Store, cls: NamedNode) -> Decision | None:
    """The decision recorded when ``cls`` was last learned, or None (learned before Engram kept
    a history, or by ``learn_classes``, which stores no scene). A few point lookups; the
    equivalent SPARQL is ``sparql/history_decision.rq``."""
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
    parents = [p for p in values.get(EVENT_PARENT, []) if isinstance(p, NamedNode)]  # before
    for listed in values.get(EVENT_PARENTS, []):  # eventParents
        parents += [NamedNode(iri) for iri in _text(listed).split()]  # type: ignore[union-attr]
    return Decision(
        scene=scene if isinstance(scene, NamedNode) else None,
        best=best if isinstance(best, NamedNode) else None,
        confidence=_float((values.get(EVENT_CONFIDENCE) or [None])[0]),
        parents=tuple(sorted(parents, key=str)),
    )


# Checkpoints -----------------------------------------------------------------------------------


@dataclasses.dataclass(frozen=True, slots=True)
class _Checkpoint:
    number: int
    covers: str
    """The largest event (IRI tail) among those it covers: every event of epochs < number."""
    low: str
    """The smallest event (IRI tail) of epoch number - 1, ``_NONE`` if it had none."""


_Last = dict[str, tuple[str, str]]
"""Class IRI -> (its last event's IRI tail, its journal entry)."""


def _checkpoints(reader: QuadReader) -> list[_Checkpoint]:
    """Every checkpoint of the history, by number (one scan of their summaries)."""
    found = []
    for quad in reader.quads(None, CHECKPOINT_SUMMARY, None, HISTORY):
        number, covers, low = quad.object.value.split(" ")  # type: ignore[union-attr]
        found.append(_Checkpoint(int(number), covers, low))
    return sorted(found, key=lambda c: c.number)


def current_epoch(reader: QuadReader) -> int:
    """The epoch new class events belong to: the number of the last checkpoint (0 before the
    first). The memory reads it once per model and keeps it in ``ModelState.history_epoch``."""
    return max((c.number for c in _checkpoints(reader)), default=0)


def _entries(reader: QuadReader, epoch: int) -> Iterable[str]:
    """The journal of ``epoch``: its events' lines and those of its sleep passes."""
    node = _epoch_node(epoch)
    for quad in reader.quads(node, HISTORY_ENTRY, None, HISTORY):
        yield quad.object.value  # type: ignore[union-attr]
    yield from _passes(reader, node)


def _legacy(reader: QuadReader, last: _Last, bound: str) -> None:
    """Fold into ``last`` the events before ``bound`` of a history written before checkpoints
    (each with its ``engram:eventState``): one scan of them all."""
    start = len(HISTORY_NS)
    for quad in reader.quads(None, EVENT_STATE, None, HISTORY):
        event, state = quad.subject.value[start:], quad.object.value  # type: ignore[union-attr]
        if event < bound:
            cls = state.rsplit(" ", 1)[-1]
            if event > last.get(cls, ("", ""))[0]:
                last[cls] = (event, f"{event} {state}")


def _fold(entries: Iterable[str], last: _Last, bound: str) -> tuple[str, str]:
    """Fold into ``last`` the journal ``entries`` before ``bound``; return the smallest and the
    largest event among all of ``entries`` (``_NONE`` and "" when there are none)."""
    low, high = _NONE, ""
    for entry in entries:
        event = entry[: entry.index(" ")]
        low, high = min(low, event), max(high, event)
        if event < bound:
            cls = entry[entry.rindex(" ") + 1 :]
            if event > last.get(cls, ("", ""))[0]:
                last[cls] = (event, entry)
    return low, high


def _read_state(reader: QuadReader, number: int) -> _Last:
    last: _Last = {}
    for quad in reader.quads(_checkpoint_node(number), CHECKPOINT_STATE, None, HISTORY):
        text = zlib.decompress(base64.b64decode(quad.object.value)).decode()  # type: ignore[union-attr]
        for entry in text.split("\n") if text else ():
            last[entry[entry.rindex(" ") + 1 :]] = (entry[: entry.index(" ")], entry)
    return last


def _last_events(reader: QuadReader, bound: str, use_checkpoints: bool) -> _Last:
    """Each class's last event before ``bound`` (an event IRI tail): the latest checkpoint that
    covers only events before ``bound``, then the events of the epochs since that may hold one
    before it; the full scan when no checkpoint does (or not ``use_checkpoints``)."""
    checkpoints = _checkpoints(reader)
    usable = [c for c in checkpoints if c.covers < bound and use_checkpoints]
    if usable:
        start = usable[-1].number
        last = _read_state(reader, start)
    else:
        start, last = 0, {}
        _legacy(reader, last, bound)
    lows = {c.number - 1: c.low for c in checkpoints}
    latest = checkpoints[-1].number if checkpoints else 0
    for epoch in range(start, latest + 1):
        # a closed epoch whose events all come at or after bound holds nothing to fold
        if epoch == start or lows.get(epoch, "") < bound or not use_checkpoints:
            _fold(_entries(reader, epoch), last, bound)
    return last


@dataclasses.dataclass(frozen=True, slots=True)
class _Written:
    """``store`` with the journal and checkpoint quads ``tx`` inserts: the history is only ever
    added to, so this is the store as it will be (read faster than through the pending view,
    which matches every quad the transaction writes on each read)."""

    store: QuadReader
    pending: list[Quad]

    @classmethod
    def of(cls, tx: Transaction, store: QuadReader) -> "_Written":
        kept = (HISTORY_ENTRY, HISTORY_PASS_EVENTS, CHECKPOINT_SUMMARY, CHECKPOINT_STATE)
        return cls(store, [q for q in tx.inserts if q.predicate in kept])

    def quads(
        self,
        subject: NamedNode | None = None,
        predicate: NamedNode | None = None,
        obj: NamedNode | Literal | None = None,
        graph: NamedNode | None = None,
    ) -> Iterator[Quad]:
        yield from self.store.quads(subject, predicate, obj, graph)
        yield from (q for q in self.pending if matches(q, subject, predicate, obj, graph))


def checkpoint(tx: Transaction, model: MemoryModel, store: QuadReader, at: dt.datetime) -> bool:
    """End a sleep pass's history: once the current epoch holds enough class events (at least
    :data:`CHECKPOINT_MIN_EVENTS` and a quarter of the live classes), or a history from before
    checkpoints has none, write checkpoint ``epoch + 1`` (every class's last event so far) and
    start that epoch. ``store`` is the store without ``tx``'s writes (which are read from
    ``tx``); call it after the pass's events are written. Returns whether it wrote one."""
    reader = _Written.of(tx, store)
    epoch = _epoch(model)
    checkpoints = _checkpoints(reader)
    entries = list(_entries(reader, epoch))
    legacy = not checkpoints and any(True for _ in reader.quads(None, EVENT_STATE, None, HISTORY))
    if len(entries) < max(CHECKPOINT_MIN_EVENTS, len(model.graph.classes) // 4) and not legacy:
        return False
    if checkpoints:
        last = _read_state(reader, checkpoints[-1].number)
        covers = checkpoints[-1].covers
    else:
        last, covers = {}, ""
        _legacy(reader, last, _NONE)
        covers = max((event for event, _ in last.values()), default="")
    low, high = _fold(entries, last, _NONE)
    covers = max(covers, high)
    text = "\n".join(entry for _, entry in sorted(last.values()))
    state = base64.b64encode(zlib.compress(text.encode(), 1)).decode()
    node = _checkpoint_node(epoch + 1)
    tx.insert(node, CHECKPOINT_SUMMARY, Literal(f"{epoch + 1} {covers} {low}"), HISTORY)
    tx.insert(node, CHECKPOINT_STATE, Literal(state), HISTORY)
    tx.insert(node, PROV_AT_TIME, _time_literal(at), HISTORY)
    model.state.history_epoch = epoch + 1
    return True


def as_of(store: QuadReader, at: dt.datetime, *, use_checkpoints: bool = True) -> list[ClassState]:
    """The classes that existed at ``at`` (learned or restored, not forgotten since), each with
    the score and level its last event before ``at`` left, sorted by IRI.

    The same answer as ``sparql/history_as_of.rq``, from the latest checkpoint before ``at``
    and the journal of its epoch (module docstring): an event IRI holds its time and sorts in
    event order, so the last event of each class before ``at`` is the largest IRI below
    ``<HISTORY_NS><ms of at + 1>``. Without a checkpoint before ``at``, one scan of every class
    event (0.23 s at 10,000 classes after 100 passes on disk; the SPARQL's grouping and join
    take 0.5-1 s). ``use_checkpoints=False`` makes that scan (to check the two agree)."""
    if at.tzinfo is None:
        raise ValueError(f"at: got {at!r}, expected a timezone-aware datetime")
    bound = f"{int(_utc(at).timestamp() * 1000) + 1:013d}"
    states = []
    times: dict[str, str] = {}  # events share times (a sleep pass's, a bulk learning's)
    for event, entry in _last_events(store, bound, use_checkpoints).values():
        _, kind, level, score, cls = entry.split(" ", 4)
        if kind == "forgotten":
            continue
        since = times.get(event[:13])
        if since is None:
            moment = dt.datetime.fromtimestamp(int(event[:13]) / 1000, dt.UTC)
            since = times[event[:13]] = moment.isoformat(timespec="milliseconds")
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
