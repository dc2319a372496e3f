"""Explanations derived on demand from the live memory (its read-only views) and, for what is
no longer live, from the ``trash`` and ``episodic`` graphs (``sparql/explain_*.rq``)."""

import datetime as dt
import math

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
from reasoners import history
from reasoners.errors import UnknownItemError
from reasoners.explain.kinds import (
    Explanation,
    ForgettingExplanation,
    LearningExplanation,
    LevelExplanation,
    NearMiss,
    ParentLink,
    PlacementExplanation,
    RecognitionExplanation,
    RestoreExplanation,
    beyond,
    checks,
)
from reasoners.labels import local
from reasoners.memory import SceneMemory
from reasoners.signature import Key, Signature

__all__ = [
    "explain",
    "explain_forgetting",
    "explain_learning",
    "explain_level",
    "explain_placement",
    "explain_scene",
    "explain_subsumption",
    "scene_signature",
]


def _near_misses(
    memory: SceneMemory, signature: Signature, exclude: set[NamedNode], limit: int = 3
) -> tuple[NearMiss, ...]:
    found = []
    # the classes the signature belongs to are skipped below: ask for a few more than needed
    for match in memory.reads.closest(signature, 3 * limit + 5):
        if match.cls in exclude:
            continue
        required = memory.reads.signature(match.cls)
        if signature.satisfies(required):
            continue
        missed = tuple(c for c in checks(required, signature) if not c.met)
        found.append(NearMiss(match.cls.value, match.similarity, missed))
        if len(found) == limit:
            break
    return tuple(found)


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
    a, b = memory.reads.learned_at(cls), memory.reads.learned_at(other)
    return (b, _number(other)) < (a, _number(cls))


def _number(cls: NamedNode) -> int:
    tail = local(cls).rsplit("-", 1)[-1]
    return int(tail) if tail.isdigit() else 0


def _learned_from(memory: SceneMemory, cls: NamedNode, item: NamedNode) -> bool:
    """Whether ``cls`` was learned from the experienced scene ``item``: the first scene stored
    as it at the moment it was learned (scene numbers grow with each update)."""
    created = memory.reads.learned_at(cls)
    first = min((i for i, t in memory.reads.seen(cls) if t == created), key=_number, default=None)
    return first == item


def explain_learning(
    memory: SceneMemory, cls: NamedNode, *, scene: NamedNode | None = None
) -> LearningExplanation:
    """Why ``cls`` was learned (raises UnknownItemError for an IRI that is not a live class)."""
    signature = memory.reads.signature(cls)
    earlier = [
        r
        for r in memory.reads.recognitions(signature)
        if r.cls != cls and _learned_before(memory, cls, r.cls)
    ]
    best = earlier[0] if earlier else None
    exclude = {cls, *(r.cls for r in earlier)}
    misses = tuple(
        m
        for m in _near_misses(memory, signature, exclude, limit=6)
        if _learned_before(memory, cls, NamedNode(m.cls))
    )[:3]
    best_cls = best.cls if best else None
    best_confidence = best.confidence if best else 0.0
    # the decision as recorded when the class was learned (PROV, reasoners.history): it names
    # the best class then, even one forgotten since
    decision = history.learned_decision(memory.store, cls)
    recorded = decision is not None and decision.scene is not None
    if decision is not None and recorded:
        best_cls, best_confidence = decision.best, decision.confidence or 0.0
        scene = scene if scene is not None else decision.scene
    return LearningExplanation(
        cls=cls.value,
        scene=scene.value if scene is not None else None,
        complexity=signature.complexity,
        best=best_cls.value if best_cls else None,
        best_complexity=round(best_confidence * signature.complexity) if best_cls else 0,
        best_confidence=best_confidence,
        threshold=memory.policy.learnThreshold,
        recognised=tuple((r.cls.value, r.confidence) for r in earlier),
        near_misses=misses,
        recorded=recorded,
    )


def explain_scene(
    memory: SceneMemory, item: NamedNode
) -> RecognitionExplanation | LearningExplanation:
    """Why an experienced scene was stored as its class: recognised (its class fitted it well
    enough), or learned (no class did)."""
    scores = memory.reads.item_scores(item)
    cls = scores.cls
    assert cls is not None  # an item's scores name its class
    signature = scene_signature(memory, item)
    required = memory.reads.signature(cls)
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
        met=checks(required, signature),
        beyond=beyond(signature, required),
        near_misses=_near_misses(
            memory, signature, {cls, *(r.cls for r in memory.reads.recognitions(signature))}
        ),
    )


def explain_subsumption(
    memory: SceneMemory, cls: NamedNode, ancestor: NamedNode | None = None
) -> PlacementExplanation:
    """Which restrictions make ``cls`` a subclass of each direct parent; with ``ancestor``,
    of that class (or which restrictions of it ``cls`` lacks)."""
    signature = memory.reads.signature(cls)
    if ancestor is not None:
        required = memory.reads.signature(ancestor)
        met = checks(required, signature)
        missed = tuple(c for c in met if not c.met)
        link = ParentLink(ancestor.value, met, beyond(signature, required))
        return PlacementExplanation(
            cls=cls.value, parents=() if missed else (link,), missed=missed, asked=ancestor.value
        )
    parents, _ = memory.reads.relatives(cls)
    links = []
    for parent in parents:
        required = memory.reads.signature(parent)
        links.append(
            ParentLink(parent.value, checks(required, signature), beyond(signature, required))
        )
    return PlacementExplanation(cls=cls.value, parents=tuple(links))


explain_placement = explain_subsumption


def explain_level(memory: SceneMemory, iri: NamedNode) -> LevelExplanation:
    """The score terms of a live class or experienced scene now, its level and its fate."""
    p = memory.policy
    scores = memory.reads.item_scores(iri)
    now = memory.reads.now()
    protected: tuple[str, ...] = ()
    if scores.kind == "class":
        t = memory.reads.score_terms(iri)
        a_d, a_c, a_s, a_r = t.weights
        mean = sum(t.children_zeta) / len(t.children_zeta) if t.children_zeta else 0.0
        terms = {
            "complexity": a_d * (t.complexity / t.max_complexity if t.max_complexity else 0.0),
            "children": a_c * mean,
            "stored": a_s * _log_ratio(t.store_count, t.max_store),
            "retrieved": a_r * _log_ratio(t.retrieve_count, t.max_retrieve),
        }
        zeta = t.zeta
        protected = tuple(
            i.value for i in memory.reads.items_of(iri) if memory.reads.item_scores(i).pinned
        )
    else:
        cls = scores.cls
        assert cls is not None
        age_s = max((now - scores.last_accessed).total_seconds(), 0.0)
        top = memory.reads.maxima()
        terms = {
            "complexity": p.episodicComplexityWeight
            * _ratio(scores.complexity, top["item_complexity"]),
            "class": p.episodicChildrenWeight * memory.reads.item_scores(cls).normalised,
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
    entry = memory.reads.trashed(iri)
    if entry is None:
        raise UnknownItemError(f"about: {iri.value} is not in the trash")
    if entry.kind == "item":
        assert entry.cls is not None
        if memory.reads.trashed(entry.cls) is not None:
            return RestoreExplanation(
                iri.value,
                False,
                f"its class {local(entry.cls)} is in the trash too; restore the class first",
                (),
            )
        return RestoreExplanation(iri.value, True, f"its class {local(entry.cls)} is live", ())
    assert entry.signature is not None
    rival = memory.reads.live_class(entry.signature)
    if rival is not None:
        return RestoreExplanation(
            iri.value, False, f"the live class {local(rival)} has the same signature", ()
        )
    with_it = tuple(
        t.value
        for t in memory.reads.trash()
        if (e := memory.reads.trashed(t)) is not None
        and e.kind == "item"
        and e.cls == iri
        and e.forgotten_at == entry.forgotten_at
    )
    return RestoreExplanation(iri.value, True, "no live class has its signature", with_it)


def explain_forgetting(memory: SceneMemory, iri: NamedNode) -> ForgettingExplanation:
    """Why ``iri`` is in the trash, from the values the trash keeps (``explain_trash_values``).

    Raises UnknownItemError when the trash does not hold it."""
    entry = memory.reads.trashed(iri)
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
        cls_entry = memory.reads.trashed(entry.cls)
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
        weak_passes=int(weak or 0),
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
    if memory.reads.trashed(iri) is not None:
        forgetting = explain_forgetting(memory, iri)
        return [forgetting, forgetting.restore]
    scores = memory.reads.item_scores(iri)  # raises UnknownItemError for anything else
    if scores.kind == "class":
        return [
            explain_learning(memory, iri),
            explain_subsumption(memory, iri),
            explain_level(memory, iri),
        ]
    return [explain_scene(memory, iri), explain_level(memory, iri)]
