"""Memory directives: scenes in, recognition, retrieval, sleep, pin, restore and scores out.

They extend ARMOR's table with its key scheme. A perception client opens a scene, sends the
primitives as ordinary ADD directives, and closes it::

    LOAD INIT ""        []                     open a scene for (client_name, reference_name)
    ADD IND CLASS       [obj, Sphere]          a primitive (Sphere, Cylinder, Cone or Plane)
    ADD DATAPROP IND    [centreX, obj, DOUBLE, 0.3]   its attributes, named as in engram.ttl
    SCENE UPDATED ""    [] or [episode IRI]    close it: encode, recognise, learn or reinforce

While a scene is open, those ADDs feed the scene, not the reference (which need not be loaded).
Each memory directive that changes the memory queues an operation as a value
(:mod:`reasoners.operations`); the scene memory runs them when the directive list commits, in
order, in the list's one transaction (:meth:`reasoners.memory.SceneMemory.commit`): a list that
fails stores no scene, and a list with two scenes stores both or neither (so a directive later
in the same list does not see a scene's effect yet).
Results come as ``queried_objects`` (the main answer, in the request's value style) and
``sparql_queried_objects`` (every detail as key/value).
"""

import datetime as dt
import logging
import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from typing import Any

from pyoxigraph import NamedNode

from api.armor.context import Context, Outcome
from api.armor.errors import MemoryDirectiveError
from api.armor.memory_explain import query_memory_explain
from api.armor.names import is_value_type, resolve, styled, to_literal
from api.protocol import ArmorDirectiveRes, QueryItem
from kg import Store
from kg.errors import InvalidPrimitiveError
from kg.primitive import ATTRIBUTES, KINDS, Kind, Primitive
from ontologies.vocab import ENGRAM_NS
from reasoners.clock import SettableClock
from reasoners.errors import MemoryReasonerError
from reasoners.memory import SceneMemory
from reasoners.operations import AdvanceClock, Pin, Restore, Retrieve, SetClock, Sleep, StoreScene
from reasoners.scoring import SCORE_DECIMALS, rounded

__all__ = ["MEMORY_COMMANDS", "MemoryDirectives", "SceneDraft", "sleep_if_due"]

log = logging.getLogger(__name__)

_KINDS: dict[str, Kind] = {kind.lower(): kind for kind in KINDS}
_SPELLINGS = {"center": "centre"}  # centerX/Y/Z, as ARMOR clients may spell it
SceneKey = tuple[str, str]


@dataclass(frozen=True)
class SceneDraft:
    """An open scene: each primitive's kind and attributes so far, as its ADD directives named
    them, parsed into :class:`~kg.primitive.Primitive` once, when the scene closes
    (:meth:`primitives`). Immutable: every change makes a copy."""

    kinds: Mapping[str, Kind] = field(default_factory=dict)
    attributes: Mapping[str, Mapping[str, float]] = field(default_factory=dict)

    def with_kind(self, name: str, kind: Kind) -> "SceneDraft":
        attributes = dict(self.attributes)
        attributes.setdefault(name, {})
        return SceneDraft({**self.kinds, name: kind}, attributes)

    def with_attribute(self, name: str, attribute: str, value: float) -> "SceneDraft":
        values = {**self.attributes.get(name, {}), attribute: value}
        return SceneDraft(self.kinds, {**self.attributes, name: values})

    def primitives(self) -> list[Primitive]:
        """The scene's primitives, in the order they were first named.

        Raises :class:`MemoryDirectiveError` for a primitive without a kind (``ADD IND
        CLASS``) and for what :meth:`Primitive.from_attributes` refuses."""
        primitives = []
        for name, attributes in self.attributes.items():
            if name not in self.kinds:
                raise MemoryDirectiveError(
                    f"primitive {name!r}: has attributes but no kind; "
                    f"send ADD IND CLASS [{name}, Kind]"
                )
            try:
                primitives.append(Primitive.from_attributes(name, self.kinds[name], attributes))
            except InvalidPrimitiveError as error:
                raise MemoryDirectiveError(str(error)) from None
        return primitives


def _memory_iri(name: str, field_name: str) -> NamedNode:
    """A memory class or item: a short name in Engram's namespace, or a full IRI."""
    return resolve(name, ENGRAM_NS.rstrip("#"), field=field_name)


class MemoryDirectives:
    """The scene memory behind the memory directives, and the scenes clients have open."""

    def __init__(self, store: Store, memory: SceneMemory | None = None) -> None:
        self.store = store
        self.memory = memory if memory is not None else SceneMemory(store)
        self.scenes: dict[SceneKey, SceneDraft] = {}


def _key(ctx: Context) -> SceneKey:
    return (ctx.client, ctx.request.reference_name)


def _errors(*more: type[Exception]) -> tuple[type[Exception], ...]:
    """The scene memory's errors, and ``more``."""
    return (MemoryReasonerError, ValueError, *more)


# Scenes ----------------------------------------------------------------------------------------


def load_init(ctx: Context) -> Outcome:
    key = _key(ctx)
    if ctx.session.scene(key) is not None:
        raise MemoryDirectiveError(
            f"LOAD INIT: {ctx.client} already has an open scene on {key[1]}; "
            "close it with SCENE UPDATED first"
        )
    ctx.session.set_scene(key, SceneDraft())
    return Outcome()


def scene_add_ind_class(ctx: Context, draft: SceneDraft) -> Outcome:
    name, kind = ctx.arg(0, "primitive"), ctx.arg(1, "primitive kind")
    local = kind.strip("<>").rsplit("#", 1)[-1]
    if local.lower() not in _KINDS:
        raise MemoryDirectiveError(
            f"args[1]: got {kind!r}, expected a primitive kind: Sphere, Cylinder, Cone or Plane"
        )
    ctx.session.set_scene(_key(ctx), draft.with_kind(name, _KINDS[local.lower()]))
    return Outcome()


def scene_add_dataprop(ctx: Context, draft: SceneDraft) -> Outcome:
    prop, name = ctx.arg(0, "attribute"), ctx.arg(1, "primitive")
    type_name, value = ctx.arg(2, "value type"), ctx.arg(3, "value")
    local = prop.strip("<>").rsplit("#", 1)[-1]
    for spelling, attribute in _SPELLINGS.items():
        if local.startswith(spelling):
            local = attribute + local[len(spelling) :]
    if not is_value_type(type_name):
        raise MemoryDirectiveError(f"args[2]: got {type_name!r}, expected DOUBLE, FLOAT or INTEGER")
    number = float(to_literal(type_name, value, field="args[3]").value)
    if local not in ATTRIBUTES:
        raise MemoryDirectiveError(
            f"args[0]: got {prop!r}, expected a primitive attribute of engram.ttl "
            "(centreX/Y/Z, axisX/Y/Z, radius, height, apexX/Y/Z, pointOnAxisX/Y/Z, "
            "hessianOffset, extentX/Y, colourR/G/B, trackingId)"
        )
    ctx.session.set_scene(_key(ctx), draft.with_attribute(name, local, number))
    return Outcome()


def _items(pairs: list[tuple[str, str]]) -> list[QueryItem]:
    return [QueryItem(key=k, value=v) for k, v in pairs]


def scene_updated(ctx: Context) -> Outcome:
    key = _key(ctx)
    draft = ctx.session.scene(key)
    if draft is None:
        raise MemoryDirectiveError(
            f"SCENE UPDATED: {ctx.client} has no open scene on {key[1]}; send LOAD INIT first"
        )
    primitives = draft.primitives()
    episode = resolve(ctx.args[0], ENGRAM_NS, field="args[0]") if ctx.args else None
    memory = ctx.scene_memory()
    try:
        memory.recognise(primitives)  # checks the scene now, so that a bad one fails the list
    except _errors() as error:
        raise MemoryDirectiveError(f"SCENE UPDATED: {error}") from None
    ctx.session.set_scene(key, None)

    def fill(result: Any, response: ArmorDirectiveRes) -> None:
        response.queried_objects = [styled(result.stored_as, ctx.style)]
        pairs = [
            ("stored_as", styled(result.stored_as, ctx.style)),
            ("learned", "true" if result.learned else "false"),
            ("confidence", f"{result.confidence:.6g}"),
            ("complexity", str(result.signature.complexity)),
            ("scene_item", styled(result.scene_item, ctx.style)),
        ]
        pairs += [
            ("recognised", f"{styled(r.cls, ctx.style)} {r.confidence:.6g}")
            for r in result.recognised
        ]
        pairs += [("parent", styled(p, ctx.style)) for p in result.parents]
        pairs += [("level", result.scores.level), ("score", f"{result.scores.normalised:.6g}")]
        response.sparql_queried_objects = _items(pairs)

    # the periodic sleep pass follows, when due, in the list's transaction too
    return Outcome(operation=StoreScene(tuple(primitives), episode), answer=fill)


def sleep_if_due(memory: SceneMemory) -> None:
    """The periodic sleep pass, when the policy says one is due, as its own transaction (the
    server's timer); a failing pass is logged, and the memory stays as before it."""
    try:
        report = memory.maybe_sleep()
    except Exception:
        log.exception("the periodic sleep pass failed; the memory is as before it")
        return
    if report is not None:
        log.info(
            "sleep pass: %d rescored, %d classes and %d items forgotten",
            report.rescored,
            len(report.forgotten_classes),
            len(report.forgotten_items),
        )


# Retrieval, sleep, pin, restore, scores ---------------------------------------------------------


def _cue(ctx: Context) -> list[Any]:
    """Relation triples from args ("Sphere isAboveOf Plane"), or the client's open scene."""
    if ctx.args:
        cue = []
        for index, text in enumerate(ctx.args):
            parts = text.split()
            if len(parts) != 3:
                raise MemoryDirectiveError(
                    f"args[{index}]: got {text!r}, expected 'Type relation Type', "
                    "e.g. 'Sphere isAboveOf Plane'"
                )
            cue.append(tuple(parts))
        return cue
    draft: SceneDraft | None = ctx.session.scene(_key(ctx))
    if draft is None:
        raise MemoryDirectiveError(
            "RETRIEVE SCENE: give the cue as args ('Sphere isAboveOf Plane', ...) or send it "
            "as an open scene (LOAD INIT, ADD ...)"
        )
    ctx.session.set_scene(_key(ctx), None)
    return draft.primitives()


def _retrieve(ctx: Context, *, spread: bool) -> Outcome:
    cue = _cue(ctx)
    memory = ctx.scene_memory()
    try:  # check the cue now, so that a bad one fails the list
        if cue and isinstance(cue[0], tuple):
            memory.encoder.cue_signature(cue)
        else:
            memory.recognise(cue)
    except _errors() as error:
        raise MemoryDirectiveError(f"RETRIEVE SCENE: {error}") from None

    def fill(result: Any, response: ArmorDirectiveRes) -> None:
        s = ctx.style
        response.queried_objects = [styled(result.recalled, s)] if result.recalled else []
        pairs = []
        if result.recalled is not None:
            pairs.append(("recalled", styled(result.recalled, s)))
        if result.exact is not None:
            pairs.append(("exact", styled(result.exact, s)))
        pairs += [
            ("generalisation", f"{styled(r.cls, s)} {r.confidence:.6g}")
            for r in result.generalisations
        ]
        pairs += [
            ("specialisation", f"{styled(m.cls, s)} {m.similarity:.6g}")
            for m in result.specialisations
        ]
        pairs += [("similar", f"{styled(m.cls, s)} {m.similarity:.6g}") for m in result.similar]
        pairs += [("branch", styled(c, s)) for c in result.branch]
        pairs += [
            ("activation", f"{styled(m.cls, s)} {m.similarity:.6g}")
            for m in (result.activation or ())
        ]
        response.sparql_queried_objects = _items(pairs)

    return Outcome(operation=Retrieve(cue, spread), answer=fill)


def retrieve_scene(ctx: Context) -> Outcome:
    return _retrieve(ctx, spread=False)


def retrieve_scene_spread(ctx: Context) -> Outcome:
    return _retrieve(ctx, spread=True)


def memory_sleep(ctx: Context) -> Outcome:
    ctx.scene_memory()  # the sleep runs at the commit; refused now without a memory

    def fill(report: Any, response: ArmorDirectiveRes) -> None:
        s = ctx.style
        response.queried_objects = [styled(c, s) for c in report.forgotten_classes]
        pairs = [("rescored", str(report.rescored))]
        pairs += [("forgotten_class", styled(c, s)) for c in report.forgotten_classes]
        pairs += [("forgotten_item", styled(i, s)) for i in report.forgotten_items]
        pairs += [
            ("level", f"{styled(c, s)} {level}")
            for c, level in sorted(report.levels.items(), key=lambda kv: kv[0].value)
        ]
        response.sparql_queried_objects = _items(pairs)

    return Outcome(operation=Sleep(), answer=fill)


def _pin(ctx: Context, pinned: bool) -> Outcome:
    iri = _memory_iri(ctx.arg(0, "class or scene item"), "args[0]")
    memory = ctx.scene_memory()
    try:
        memory.reads.item_scores(iri)  # checks the item is live now
    except _errors(KeyError) as error:
        raise MemoryDirectiveError(f"args[0]: {error}") from None
    return Outcome(operation=Pin(iri, pinned))


def memory_pin(ctx: Context) -> Outcome:
    return _pin(ctx, True)


def memory_unpin(ctx: Context) -> Outcome:
    return _pin(ctx, False)


def memory_restore(ctx: Context) -> Outcome:
    iri = _memory_iri(ctx.arg(0, "forgotten class or scene item"), "args[0]")
    memory = ctx.scene_memory()
    if iri not in memory.reads.trash():
        raise MemoryDirectiveError(f"args[0]: {iri.value} is not in the trash")

    def fill(restored: Any, response: ArmorDirectiveRes) -> None:
        response.queried_objects = [styled(i, ctx.style) for i in restored]

    return Outcome(operation=Restore(iri), answer=fill)


def _scores(ctx: Context) -> Any:
    iri = _memory_iri(ctx.arg(0, "class or scene item"), "args[0]")
    memory = ctx.scene_memory()
    try:
        return memory.reads.item_scores(iri)
    except _errors(KeyError) as error:
        raise MemoryDirectiveError(f"args[0]: {error}") from None


def query_memory_scores(ctx: Context) -> Outcome:
    scores = _scores(ctx)
    pairs = [
        ("kind", scores.kind),
        ("level", scores.level),
        ("normalised_score", _score(scores.normalised)),
        ("raw_score", f"{scores.raw_score:.6g}"),
        ("sleep_level", scores.stored_level or ""),
        ("complexity", str(scores.complexity)),
        ("store_count", str(scores.store_count)),
        ("retrieve_count", str(scores.retrieve_count)),
        ("consecutive_weak", str(scores.consecutive_weak)),
        ("pinned", "true" if scores.pinned else "false"),
        ("created", scores.created.isoformat()),
        ("last_accessed", scores.last_accessed.isoformat()),
    ]
    if scores.cls is not None:
        pairs.append(("class", styled(scores.cls, ctx.style)))
    return Outcome(
        queried_objects=[_score(scores.normalised)], sparql_queried_objects=_items(pairs)
    )


def _score(normalised: float) -> str:
    """A normalised score as reported: six decimals, as the analysts' query rounds it."""
    return f"{rounded(normalised):.{SCORE_DECIMALS}f}"


def query_memory_level(ctx: Context) -> Outcome:
    return Outcome(queried_objects=[_scores(ctx).level])


# Clock ------------------------------------------------------------------------------------------


def _settable_clock(ctx: Context) -> SettableClock:
    clock = ctx.scene_memory().clock
    if not isinstance(clock, SettableClock):
        raise MemoryDirectiveError(
            f"{ctx.key}: the memory's clock is the real one; start the server with "
            "ENGRAM_CLOCK_SETTABLE=true to set it (tests, demos, simulated days)"
        )
    return clock


def _clock_answer(now: Any, response: ArmorDirectiveRes) -> None:
    response.queried_objects = [now.isoformat()]


def memory_clock_set(ctx: Context) -> Outcome:
    clock = _settable_clock(ctx)
    text = ctx.arg(0, "time")
    try:
        when = dt.datetime.fromisoformat(text)
    except ValueError:
        when = None
    if when is None or when.tzinfo is None:
        raise MemoryDirectiveError(
            f"args[0]: got {text!r}, expected an ISO 8601 time with its offset, "
            "e.g. 2026-01-02T09:00:00+00:00"
        )
    if when < clock():
        raise MemoryDirectiveError(
            f"args[0]: got {text!r}, expected {clock().isoformat()} or later "
            "(the memory's clock never goes back)"
        )
    return Outcome(operation=SetClock(when), answer=_clock_answer)


def memory_clock_advance(ctx: Context) -> Outcome:
    _settable_clock(ctx)  # refused now, not at the commit, when the clock is the real one
    text = ctx.arg(0, "seconds")
    try:
        seconds = float(text) if text.strip().isascii() else math.nan
    except ValueError:
        seconds = math.nan
    if not 0 <= seconds < 1e11:  # nan and inf fail too
        raise MemoryDirectiveError(
            f"args[0]: got {text!r}, expected a number of seconds from 0 to 1e11"
        )
    return Outcome(operation=AdvanceClock(seconds), answer=_clock_answer)


def query_memory_clock(ctx: Context) -> Outcome:
    return Outcome(queried_objects=[ctx.scene_memory().clock().isoformat()])


MEMORY_COMMANDS: dict[str, tuple[Callable[[Context], Outcome], str]] = {
    "LOAD_INIT_": (load_init, "[]"),
    "SCENE_UPDATED_": (scene_updated, "[] or [episode IRI]"),
    "RETRIEVE_SCENE_": (retrieve_scene, "['Type relation Type', ...] or an open scene"),
    "RETRIEVE_SCENE_SPREAD": (retrieve_scene_spread, "['Type relation Type', ...]"),
    "MEMORY_SLEEP_": (memory_sleep, "[]"),
    "MEMORY_PIN_": (memory_pin, "[class or item]"),
    "MEMORY_UNPIN_": (memory_unpin, "[class or item]"),
    "MEMORY_RESTORE_": (memory_restore, "[class or item]"),
    "QUERY_MEMORY_SCORES": (query_memory_scores, "[class or item]"),
    "QUERY_MEMORY_LEVEL": (query_memory_level, "[class or item]"),
    "QUERY_MEMORY_EXPLAIN": (query_memory_explain, "[class, item or forgotten IRI]"),
    "MEMORY_CLOCK_SET": (memory_clock_set, "[ISO 8601 time with offset]"),
    "MEMORY_CLOCK_ADVANCE": (memory_clock_advance, "[seconds]"),
    "QUERY_MEMORY_CLOCK": (query_memory_clock, "[]"),
}
SCENE_ADDS: dict[str, Callable[[Context, SceneDraft], Outcome]] = {
    "ADD_IND_CLASS": scene_add_ind_class,
    "ADD_DATAPROP_IND": scene_add_dataprop,
}
"""ADD directives that feed an open scene instead of the reference."""
