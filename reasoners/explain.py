"""Explanations of the scene memory's decisions, derived on demand and rendered in words.

Nothing here writes. Each explanation is a frozen dataclass (its fields are the structured
answer, :func:`to_jsonable` turns it into JSON) with a ``words`` property saying it as a
sentence. They are derived from the live memory (its public read-only views) and, for what is
no longer live, from the ``trash`` and ``episodic`` graphs through ``sparql/explain_*.rq``:

- :class:`RecognitionExplanation`: an experienced scene stored under a class it belonged to:
  which restrictions of the class the scene met, what the scene had beyond them, the confidence
  arithmetic d(class)/d(scene) against the learn threshold, and the nearest classes it missed.
- :class:`LearningExplanation`: why a class was learned: no class learned before it fitted the
  scene well enough (the best confidence against the threshold), and the near misses.
- :class:`PlacementExplanation`: which restrictions make a class a subclass of each parent.
- :class:`LevelExplanation`: the score terms now, the level they give, the consecutive WEAK
  passes, the grace period and pins, and whether the next sleep pass would forget it.
- :class:`ForgettingExplanation` and :class:`RestoreExplanation`: why something is in the
  trash, and whether (and with what) it can come back.

A learning explanation compares the class with the classes learned before it that are still
live: a class forgotten since then no longer takes part (the memory keeps no history yet).

>>> import datetime as dt
>>> from kg import Store
>>> from reasoners.memory import SceneMemory
>>> from reasoners.primitives import Primitive
>>> memory = SceneMemory(Store(), clock=lambda: dt.datetime(2025, 1, 1, tzinfo=dt.UTC))
>>> ball = Primitive("ball", "Sphere", centre=(.3, .3, .3), radius=.05)
>>> table = Primitive("table", "Plane", centre=(.3, .1, .1), axis=(0, 0, 1))
>>> stored = memory.store_scene([ball, table])
>>> print(explain_learning(memory, stored.stored_as).words)  # doctest: +NORMALIZE_WHITESPACE
I learned Scene-1 because no class I knew before it fitted its scene: I knew none.
"""

import dataclasses
import datetime as dt
import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

from pyoxigraph import NamedNode

from ontologies.vocab import (
    CONSECUTIVE_WEAK_COUNT,
    CREATED,
    EPISODIC,
    PINNED,
    RETRIEVE_COUNT,
    SCORE,
    SPATIAL_INVERSES,
    STORE_COUNT,
    TRASH,
)
from reasoners.errors import UnknownItemError
from reasoners.memory import SceneMemory
from reasoners.scoring import WEAK
from reasoners.signature import Key, Signature

__all__ = [
    "Explanation",
    "ForgettingExplanation",
    "LearningExplanation",
    "LevelExplanation",
    "NearMiss",
    "PlacementExplanation",
    "RecognitionExplanation",
    "RestoreExplanation",
    "RestrictionCheck",
    "explain",
    "explain_forgetting",
    "explain_learning",
    "explain_level",
    "explain_placement",
    "explain_scene",
    "explain_subsumption",
    "local",
    "scene_signature",
    "to_jsonable",
]

_RELATION_WORDS = {
    "isAboveOf": "above",
    "isBelowOf": "below",
    "isRightOf": "right of",
    "isLeftOf": "left of",
    "isBehindOf": "behind",
    "isInFrontOf": "in front of",
    "isParallelWith": "parallel with",
    "isPerpendicularWith": "perpendicular to",
    "isCoaxialWith": "coaxial with",
    "isAlongXWith": "aligned along x with",
    "isAlongYWith": "aligned along y with",
    "isAlongZWith": "aligned along z with",
}
_KINDS = ("sphere", "cylinder", "cone", "plane")


def local(iri: NamedNode | str) -> str:
    """The local name of an IRI (after ``#`` or the last ``/``)."""
    text = iri.value if isinstance(iri, NamedNode) else iri
    return text.rsplit("#", 1)[-1].rsplit("/", 1)[-1]


def _times(n: int) -> str:
    return {0: "never", 1: "once", 2: "twice"}.get(n, f"{n} times")


def _say_count(n: int, noun: str) -> str:
    return f"{n} {noun}{'' if n == 1 else 's'}"


@dataclass(frozen=True)
class RestrictionCheck:
    """One restriction ``≥required property.type`` and how many objects a scene had for it."""

    prop: str
    leaf: str
    required: int
    found: int

    @property
    def met(self) -> bool:
        return self.found >= self.required

    def _phrase(self) -> str:
        name = self.prop
        kind = next((k for k in _KINDS if name.lower().startswith(k)), "")
        rest = name[len(kind) :]
        relation = _RELATION_WORDS.get(rest[:1].lower() + rest[1:], rest)
        return f"a {kind} {relation}" if kind else relation

    @property
    def words(self) -> str:
        """The restriction: "a sphere above at least 1 plane" for sphereIsAboveOf ≥1 Plane."""
        return f"{self._phrase()} at least {_say_count(self.required, self.leaf.lower())}"

    @property
    def extra_words(self) -> str:
        """For a part beyond a class (``required`` more than the class asks, ``found`` in all):
        "a plane below 2 spheres (1 more)"."""
        leaf = self.leaf.lower()
        if self.found == self.required:
            return f"{self._phrase()} {_say_count(self.found, leaf)}"
        return f"{self._phrase()} {_say_count(self.found, leaf)} ({self.required} more)"


def _checks(required: Signature, found: Signature) -> tuple[RestrictionCheck, ...]:
    return tuple(
        RestrictionCheck(local(p), local(t), n, found.get((p, t), 0))
        for (p, t), n in required.items()
    )


def _beyond(signature: Signature, cls: Signature) -> tuple[RestrictionCheck, ...]:
    """What ``signature`` has beyond ``cls``: each key with the part of its count ``cls`` does
    not ask for (``required`` is that part, ``found`` the whole count)."""
    extra = []
    for (p, t), n in signature.items():
        asked = cls.get((p, t), 0)
        if n > asked:
            extra.append(RestrictionCheck(local(p), local(t), n - asked, n))
    return tuple(extra)


def _list(checks: Sequence[RestrictionCheck], *, found: bool = True) -> str:
    parts = [f"{c.words} (it had {c.found})" if found else c.extra_words for c in checks]
    return "; ".join(parts) if parts else "nothing"


@dataclass(frozen=True)
class NearMiss:
    """A class a scene did not belong to, how similar they were, and the restrictions it missed."""

    cls: str
    similarity: float
    missed: tuple[RestrictionCheck, ...]

    @property
    def words(self) -> str:
        return f"{local(self.cls)} (similarity {self.similarity:.2f}) asks for " + _list(
            self.missed
        )


def _near_misses(
    memory: SceneMemory, signature: Signature, exclude: set[NamedNode], limit: int = 3
) -> tuple[NearMiss, ...]:
    found = []
    # the classes the signature belongs to are skipped below: ask for a few more than needed
    for match in memory.closest(signature, 3 * limit + 5):
        if match.cls in exclude:
            continue
        required = memory.signature(match.cls)
        if signature.satisfies(required):
            continue
        missed = tuple(c for c in _checks(required, signature) if not c.met)
        found.append(NearMiss(match.cls.value, match.similarity, missed))
        if len(found) == limit:
            break
    return tuple(found)


@dataclass(frozen=True)
class RecognitionExplanation:
    """Why an experienced scene was stored under a class it belonged to."""

    kind = "recognition"
    scene: str
    stored_as: str
    scene_complexity: int
    class_complexity: int
    confidence: float
    threshold: float
    met: tuple[RestrictionCheck, ...]
    beyond: tuple[RestrictionCheck, ...]
    """What the scene had that the class does not ask for."""
    near_misses: tuple[NearMiss, ...]

    @property
    def words(self) -> str:
        scene, cls = local(self.scene), local(self.stored_as)
        text = (
            f"I recognised {scene} as {cls}: it met all {_say_count(len(self.met), 'restriction')}"
            f" of {cls}: {_list(self.met)}. Confidence = d({cls}) / d(scene) = "
            f"{self.class_complexity}/{self.scene_complexity} = {self.confidence:.2f}, "
            f"at least the learn threshold {self.threshold:g}, so I reinforced {cls}."
        )
        if self.beyond:
            text += f" Beyond {cls} the scene had {_list(self.beyond, found=False)}."
        return text


@dataclass(frozen=True)
class LearningExplanation:
    """Why a class was learned: no class learned before it fitted its scene well enough."""

    kind = "learning"
    cls: str
    scene: str | None
    """The experienced scene it was learned from, when known."""
    complexity: int
    best: str | None
    """The most confident class learned before it that the scene belonged to."""
    best_complexity: int
    best_confidence: float
    threshold: float
    recognised: tuple[tuple[str, float], ...]
    """Every earlier class the scene belonged to, with its confidence."""
    near_misses: tuple[NearMiss, ...]

    @property
    def words(self) -> str:
        cls = local(self.cls)
        if self.best is None:
            text = f"I learned {cls} because no class I knew before it fitted its scene"
            if not self.near_misses:
                return text + ": I knew none."
            return (
                text
                + ": its scene belonged to none of them. The closest: "
                + "; ".join(m.words for m in self.near_misses)
                + "."
            )
        best = local(self.best)
        text = (
            f"I learned {cls} because the best class I knew, {best}, fitted its scene with "
            f"confidence d({best}) / d(scene) = {self.best_complexity}/{self.complexity} = "
            f"{self.best_confidence:.2f}, below the learn threshold {self.threshold:g}."
        )
        if self.near_misses:
            text += " Closer classes missed: " + "; ".join(m.words for m in self.near_misses) + "."
        return text


@dataclass(frozen=True)
class ParentLink:
    """A direct parent and the restrictions of it that the child meets."""

    parent: str
    restrictions: tuple[RestrictionCheck, ...]
    adds: tuple[RestrictionCheck, ...]
    """What the child asks for beyond the parent."""


@dataclass(frozen=True)
class PlacementExplanation:
    """Why a class sits where it does in the graph: which restrictions make it a subclass of
    each direct parent (or of a chosen ancestor), or which it lacks."""

    kind = "placement"
    cls: str
    parents: tuple[ParentLink, ...]
    missed: tuple[RestrictionCheck, ...] = ()
    """With :func:`explain_subsumption` for a class it is not a kind of: what it lacks."""
    asked: str | None = None
    """With :func:`explain_subsumption`: the class asked about."""

    @property
    def is_kind(self) -> bool:
        return not self.missed

    @property
    def words(self) -> str:
        cls = local(self.cls)
        if self.asked is not None and self.missed:
            return (
                f"{cls} is not a kind of {local(self.asked)}: {local(self.asked)} asks for "
                f"{_list(self.missed)}."
            )
        if not self.parents:
            return f"{cls} is directly under Scene: no class I know is more general than it."
        parts = []
        for link in self.parents:
            part = (
                f"{cls} is a kind of {local(link.parent)} because it meets every restriction "
                f"of {local(link.parent)}: {_list(link.restrictions)}"
            )
            if link.adds:
                part += f"; it adds {_list(link.adds, found=False)}"
            parts.append(part)
        return ". ".join(parts) + "."


@dataclass(frozen=True)
class LevelExplanation:
    """A live class's or experienced scene's score terms now, its level and its fate."""

    kind = "level"
    about: str
    item_kind: str
    """"class" or "item"."""
    terms: dict[str, float]
    """Each weighted term of ζ (for an item, ``decay`` is subtracted)."""
    zeta: float
    normalised: float
    level: str
    high_threshold: float
    weak_threshold: float
    consecutive_weak: int
    passes_to_forget: int
    age_s: float
    grace_s: float
    pinned: bool
    protected_by: tuple[str, ...]
    """Pinned experienced scenes that keep this class."""

    @property
    def next_pass_forgets(self) -> bool:
        """Whether the next sleep pass forgets it if its level stays what it is now."""
        return (
            self.level == WEAK
            and self.consecutive_weak + 1 >= self.passes_to_forget
            and self.age_s >= self.grace_s
            and not self.pinned
            and not self.protected_by
        )

    @property
    def words(self) -> str:
        name = local(self.about)
        terms = " + ".join(f"{k} {v:.3f}" for k, v in self.terms.items() if k != "decay")
        if "decay" in self.terms:
            terms += f" - decay {self.terms['decay']:.3f}"
        text = (
            f"{name}'s score is {terms} = {self.zeta:.3f}, {self.normalised:.2f} of the best, "
            f"so its level is {self.level} (HIGH above {self.high_threshold:g}, WEAK below "
            f"{self.weak_threshold:g}). It was WEAK at {self.consecutive_weak} consecutive "
            f"sleep pass{'' if self.consecutive_weak == 1 else 'es'}; I forget after "
            f"{self.passes_to_forget}"
        )
        if self.pinned:
            return text + ", but it is pinned, so I keep it."
        if self.protected_by:
            return text + f", but the pinned scene {local(self.protected_by[0])} keeps it."
        if self.age_s < self.grace_s:
            return text + (
                f", but it is {self.age_s / 3600:.1f} h old, within the grace period of "
                f"{self.grace_s / 3600:.1f} h."
            )
        if self.next_pass_forgets:
            return text + ", so the next sleep pass forgets it if it is still WEAK."
        return text + "."


@dataclass(frozen=True)
class RestoreExplanation:
    """Whether a trashed class or scene can be restored, and what would come back with it."""

    kind = "restore"
    about: str
    restorable: bool
    reason: str
    brings_back: tuple[str, ...]

    @property
    def words(self) -> str:
        name = local(self.about)
        if not self.restorable:
            return f"I cannot restore {name}: {self.reason}."
        more = ""
        if self.brings_back:
            more = " with " + ", ".join(local(i) for i in self.brings_back)
        return f"I can restore {name}{more}, exactly as it was ({self.reason})."


@dataclass(frozen=True)
class ForgettingExplanation:
    """Why a class or experienced scene is in the trash, from the values it had then."""

    kind = "forgetting"
    about: str
    item_kind: str
    forgotten_at: dt.datetime
    created: dt.datetime | None
    weak_passes: int
    """Consecutive WEAK passes at the pass that forgot it (the stored count plus that pass)."""
    passes_to_forget: int
    grace_s: float
    pinned: bool
    score: float | None
    store_count: int | None
    retrieve_count: int | None
    with_class: str | None
    """For a scene forgotten with its class: that class."""
    restore: RestoreExplanation

    @property
    def words(self) -> str:
        name = local(self.about)
        when = self.forgotten_at.isoformat(timespec="seconds")
        if self.with_class is not None:
            text = f"I forgot {name} at {when} together with its class {local(self.with_class)}."
        else:
            age = ""
            if self.created is not None:
                hours = (self.forgotten_at - self.created).total_seconds() / 3600
                age = (
                    f", it was {hours:.1f} h old (the grace period is {self.grace_s / 3600:.1f} h)"
                )
            counts = ""
            if self.store_count is not None:
                counts = f"; it had been stored {_times(self.store_count)} and " + (
                    f"retrieved {_times(self.retrieve_count)}"
                    if self.retrieve_count
                    else "never retrieved"
                )
            text = (
                f"I forgot {name} at {when} because its level was WEAK at "
                f"{self.weak_passes} consecutive sleep passes (I forget after "
                f"{self.passes_to_forget}){age}, and it was not pinned{counts}."
            )
        return text + " " + self.restore.words


Explanation = (
    RecognitionExplanation
    | LearningExplanation
    | PlacementExplanation
    | LevelExplanation
    | ForgettingExplanation
    | RestoreExplanation
)


def _plain(value: Any) -> Any:
    if isinstance(value, dt.datetime):
        return value.isoformat()
    if isinstance(value, dict):
        return {k: _plain(v) for k, v in value.items()}
    if isinstance(value, list | tuple):
        return [_plain(v) for v in value]
    return value


def _part(value: Any) -> dict[str, Any]:
    """A restriction check, near miss or parent link as JSON, with its words when it has some."""
    body = {
        spec.name: [_part(v) for v in item]
        if isinstance(item := getattr(value, spec.name), tuple)
        and item
        and dataclasses.is_dataclass(item[0])
        else _plain(item)
        for spec in dataclasses.fields(value)
    }
    if hasattr(value, "words"):
        body["words"] = value.words
    if hasattr(value, "met"):
        body["met"] = value.met
    return body


def to_jsonable(explanation: Explanation) -> dict[str, Any]:
    """The explanation as JSON: its fields, its ``kind`` and its ``words``."""

    body: dict[str, Any] = {"kind": explanation.kind, "words": explanation.words}
    for spec in dataclasses.fields(explanation):
        value = getattr(explanation, spec.name)
        if isinstance(value, RestoreExplanation):
            body[spec.name] = to_jsonable(value)
        elif isinstance(value, tuple) and value and dataclasses.is_dataclass(value[0]):
            body[spec.name] = [_part(v) for v in value]
        else:
            body[spec.name] = _plain(value)
    return body


# Derivations -----------------------------------------------------------------------------------


def scene_signature(memory: SceneMemory, item: NamedNode, graph: NamedNode = EPISODIC) -> Signature:
    """The signature of an experienced scene, recomputed from its stored primitives and
    relations in ``graph`` (``episodic``, or ``trash`` for a forgotten one)."""
    encoder = memory.encoder
    kinds = {leaf: leaf for leaf in encoder.leaf.values()}
    links: set[tuple[NamedNode, NamedNode, NamedNode]] = set()  # (property, object, its leaf)
    for row in memory.store.select("explain_scene_relations", item=item, g=graph):
        s, o, relation = row["s"], row["o"], row["relation"]
        s_kind, o_kind = row["sKind"], row["oKind"]
        if not all(isinstance(t, NamedNode) for t in (s, o, relation, s_kind, o_kind)):
            continue
        s_leaf, o_leaf = kinds.get(s_kind), kinds.get(o_kind)  # type: ignore[arg-type]
        inverse = SPATIAL_INVERSES.get(relation)  # type: ignore[arg-type]
        if s_leaf is None or o_leaf is None or inverse is None:
            continue
        links.add((encoder.properties[(s_leaf, relation)], o, o_leaf))  # type: ignore[index,arg-type]
        links.add((encoder.properties[(o_leaf, inverse)], s, s_leaf))  # type: ignore[arg-type]
    counts: dict[Key, int] = {}
    for prop, _, leaf in links:
        counts[(prop, leaf)] = counts.get((prop, leaf), 0) + 1
    return Signature(counts)


def _learned_before(memory: SceneMemory, cls: NamedNode, other: NamedNode) -> bool:
    """Whether ``other`` was learned before ``cls`` (by time, then by number)."""
    a, b = memory.learned_at(cls), memory.learned_at(other)
    return (b, _number(other)) < (a, _number(cls))


def _number(cls: NamedNode) -> int:
    tail = local(cls).rsplit("-", 1)[-1]
    return int(tail) if tail.isdigit() else 0


def _learned_from(memory: SceneMemory, cls: NamedNode, item: NamedNode) -> bool:
    """Whether ``cls`` was learned from the experienced scene ``item``: the first scene stored
    as it at the moment it was learned (scene numbers grow with each update)."""
    created = memory.learned_at(cls)
    first = min((i for i, t in memory.seen(cls) if t == created), key=_number, default=None)
    return first == item


def explain_learning(
    memory: SceneMemory, cls: NamedNode, *, scene: NamedNode | None = None
) -> LearningExplanation:
    """Why ``cls`` was learned (raises UnknownItemError for an IRI that is not a live class)."""
    signature = memory.signature(cls)
    earlier = [
        r
        for r in memory.recognitions(signature)
        if r.cls != cls and _learned_before(memory, cls, r.cls)
    ]
    best = earlier[0] if earlier else None
    exclude = {cls, *(r.cls for r in earlier)}
    misses = tuple(
        m
        for m in _near_misses(memory, signature, exclude, limit=6)
        if _learned_before(memory, cls, NamedNode(m.cls))
    )[:3]
    return LearningExplanation(
        cls=cls.value,
        scene=scene.value if scene is not None else None,
        complexity=signature.complexity,
        best=best.cls.value if best else None,
        best_complexity=best.complexity if best else 0,
        best_confidence=best.confidence if best else 0.0,
        threshold=memory.policy.learnThreshold,
        recognised=tuple((r.cls.value, r.confidence) for r in earlier),
        near_misses=misses,
    )


def explain_scene(
    memory: SceneMemory, item: NamedNode
) -> RecognitionExplanation | LearningExplanation:
    """Why an experienced scene was stored as its class: recognised (its class fitted it well
    enough), or learned (no class did)."""
    scores = memory.item_scores(item)
    cls = scores.cls
    assert cls is not None  # an item's scores name its class
    signature = scene_signature(memory, item)
    required = memory.signature(cls)
    if required == signature and _learned_from(memory, cls, item):
        return explain_learning(memory, cls, scene=item)
    d_scene = signature.complexity or scores.complexity
    return RecognitionExplanation(
        scene=item.value,
        stored_as=cls.value,
        scene_complexity=d_scene,
        class_complexity=required.complexity,
        confidence=required.complexity / d_scene if d_scene else 0.0,
        threshold=memory.policy.learnThreshold,
        met=_checks(required, signature),
        beyond=_beyond(signature, required),
        near_misses=_near_misses(
            memory, signature, {cls, *(r.cls for r in memory.recognitions(signature))}
        ),
    )


def explain_subsumption(
    memory: SceneMemory, cls: NamedNode, ancestor: NamedNode | None = None
) -> PlacementExplanation:
    """Which restrictions make ``cls`` a subclass of each direct parent; with ``ancestor``,
    of that class (or which restrictions of it ``cls`` lacks)."""
    signature = memory.signature(cls)
    if ancestor is not None:
        required = memory.signature(ancestor)
        checks = _checks(required, signature)
        missed = tuple(c for c in checks if not c.met)
        link = ParentLink(ancestor.value, checks, _beyond(signature, required))
        return PlacementExplanation(
            cls=cls.value, parents=() if missed else (link,), missed=missed, asked=ancestor.value
        )
    parents, _ = memory.relatives(cls)
    links = []
    for parent in parents:
        required = memory.signature(parent)
        links.append(
            ParentLink(parent.value, _checks(required, signature), _beyond(signature, required))
        )
    return PlacementExplanation(cls=cls.value, parents=tuple(links))


explain_placement = explain_subsumption


def explain_level(memory: SceneMemory, iri: NamedNode) -> LevelExplanation:
    """The score terms of a live class or experienced scene now, its level and its fate."""
    p = memory.policy
    scores = memory.item_scores(iri)
    now = memory.now()
    protected: tuple[str, ...] = ()
    if scores.kind == "class":
        t = memory.score_terms(iri)
        a_d, a_c, a_s, a_r = t.weights
        mean = sum(t.children_zeta) / len(t.children_zeta) if t.children_zeta else 0.0
        terms = {
            "complexity": a_d * (t.complexity / t.max_complexity if t.max_complexity else 0.0),
            "children": a_c * mean,
            "stored": a_s * _log_ratio(t.store_count, t.max_store),
            "retrieved": a_r * _log_ratio(t.retrieve_count, t.max_retrieve),
        }
        zeta = t.zeta
        protected = tuple(i.value for i in memory.items_of(iri) if memory.item_scores(i).pinned)
    else:
        cls = scores.cls
        assert cls is not None
        age_s = max((now - scores.last_accessed).total_seconds(), 0.0)
        top = memory.maxima()
        terms = {
            "complexity": p.episodicComplexityWeight
            * _ratio(scores.complexity, top["item_complexity"]),
            "class": p.episodicChildrenWeight * memory.item_scores(cls).normalised,
            "stored": p.episodicStoreWeight * _log_ratio(scores.store_count, top["store"]),
            "retrieved": p.episodicRetrieveWeight
            * _log_ratio(scores.retrieve_count, top["retrieve"]),
            "decay": p.decayWeight * math.log1p(age_s / p.decayTimeConstantSeconds),
        }
        zeta = scores.raw_score
    return LevelExplanation(
        about=iri.value,
        item_kind=scores.kind,
        terms=terms,
        zeta=zeta,
        normalised=scores.normalised,
        level=scores.level,
        high_threshold=p.highLevelThreshold,
        weak_threshold=p.weakLevelThreshold,
        consecutive_weak=scores.consecutive_weak,
        passes_to_forget=p.weakPassesToForget,
        age_s=(now - scores.created).total_seconds(),
        grace_s=p.forgetGracePeriodSeconds,
        pinned=scores.pinned,
        protected_by=protected,
    )


def _ratio(value: int, maximum: int) -> float:
    return value / maximum if maximum else 0.0


def _log_ratio(value: int, maximum: int) -> float:
    return math.log1p(value) / math.log1p(maximum) if maximum > 0 else 0.0


def _restore(memory: SceneMemory, iri: NamedNode) -> RestoreExplanation:
    entry = memory.trashed(iri)
    if entry is None:
        raise UnknownItemError(f"about: {iri.value} is not in the trash")
    if entry.kind == "item":
        assert entry.cls is not None
        if memory.trashed(entry.cls) is not None:
            return RestoreExplanation(
                iri.value,
                False,
                f"its class {local(entry.cls)} is in the trash too; restore the class first",
                (),
            )
        return RestoreExplanation(iri.value, True, f"its class {local(entry.cls)} is live", ())
    assert entry.signature is not None
    rival = memory.live_class(entry.signature)
    if rival is not None:
        return RestoreExplanation(
            iri.value, False, f"the live class {local(rival)} has the same signature", ()
        )
    with_it = tuple(
        t.value
        for t in memory.trash()
        if (e := memory.trashed(t)) is not None
        and e.kind == "item"
        and e.cls == iri
        and e.forgotten_at == entry.forgotten_at
    )
    return RestoreExplanation(iri.value, True, "no live class has its signature", with_it)


def explain_forgetting(memory: SceneMemory, iri: NamedNode) -> ForgettingExplanation:
    """Why ``iri`` is in the trash, from the values the trash keeps (``explain_trash_values``).

    Raises UnknownItemError when the trash does not hold it."""
    entry = memory.trashed(iri)
    if entry is None:
        raise UnknownItemError(f"about: {iri.value} is not in the trash")
    values = {
        row["p"]: row["o"] for row in memory.store.select("explain_trash_values", s=iri, g=TRASH)
    }
    p = memory.policy

    def number(prop: NamedNode) -> float | None:
        term = values.get(prop)
        return float(term.value) if term is not None else None

    with_class = None
    if entry.kind == "item" and entry.cls is not None:
        cls_entry = memory.trashed(entry.cls)
        if cls_entry is not None and cls_entry.forgotten_at == entry.forgotten_at:
            with_class = entry.cls.value
    created = values.get(CREATED)
    weak = number(CONSECUTIVE_WEAK_COUNT)
    store_count, retrieve_count = number(STORE_COUNT), number(RETRIEVE_COUNT)
    return ForgettingExplanation(
        about=iri.value,
        item_kind=entry.kind,
        forgotten_at=entry.forgotten_at,
        created=dt.datetime.fromisoformat(created.value) if created is not None else None,
        weak_passes=int(weak or 0) + 1,
        passes_to_forget=p.weakPassesToForget,
        grace_s=p.forgetGracePeriodSeconds,
        pinned=(values.get(PINNED) is not None and values[PINNED].value == "true"),
        score=number(SCORE),
        store_count=int(store_count) if store_count is not None else None,
        retrieve_count=int(retrieve_count) if retrieve_count is not None else None,
        with_class=with_class,
        restore=_restore(memory, iri),
    )


def explain(memory: SceneMemory, iri: NamedNode) -> list[Explanation]:
    """Every explanation that applies to ``iri``: a live class (learning, placement, level), a
    live experienced scene (recognition or learning, level), or something in the trash
    (forgetting, restore). Raises UnknownItemError for an IRI the memory never held."""
    if memory.trashed(iri) is not None:
        forgetting = explain_forgetting(memory, iri)
        return [forgetting, forgetting.restore]
    scores = memory.item_scores(iri)  # raises UnknownItemError for anything else
    if scores.kind == "class":
        return [
            explain_learning(memory, iri),
            explain_subsumption(memory, iri),
            explain_level(memory, iri),
        ]
    return [explain_scene(memory, iri), explain_level(memory, iri)]
