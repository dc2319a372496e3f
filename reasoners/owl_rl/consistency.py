"""The OWL 2 RL inconsistency rules (those whose head is ``false``), over a closed engine.

Each clash names its rule (the identifiers of the OWL 2 Profiles document, section 4.3) and the
terms involved, so a user can see why the ontology is inconsistent, e.g.
``cax-dw: <ex:a> is a member of the disjoint classes <ex:Cube> and <ex:Sphere>``.

>>> from reasoners.owl_rl.engine import Engine
>>> from reasoners.owl_rl._terms import TYPE, NOTHING
>>> e = Engine()
>>> e.add_all([("<a>", TYPE, NOTHING)])
>>> e.run()
>>> [clash.rule for clash in clashes(e)]
['cls-nothing2']
"""

from collections.abc import Iterator
from dataclasses import dataclass
from itertools import combinations

from reasoners.owl_rl._terms import (
    ALL_DIFFERENT,
    ALL_DISJOINT_CLASSES,
    ALL_DISJOINT_PROPERTIES,
    ASSERTION_PROPERTY,
    ASYMMETRIC,
    COMPLEMENT_OF,
    DIFFERENT_FROM,
    DISJOINT_WITH,
    DISTINCT_MEMBERS,
    IRREFLEXIVE,
    MAX_CARDINALITY,
    MAX_QUALIFIED_CARDINALITY,
    MEMBERS,
    NOTHING,
    ON_CLASS,
    ON_PROPERTY,
    PROPERTY_DISJOINT_WITH,
    SAME_AS,
    SOURCE_INDIVIDUAL,
    TARGET_INDIVIDUAL,
    TARGET_VALUE,
    THING,
    TYPE,
    numeric_value,
)
from reasoners.owl_rl.engine import Engine

__all__ = ["Clash", "clashes"]


@dataclass(frozen=True)
class Clash:
    """One violated inconsistency rule: its OWL 2 RL name, a sentence, and the terms involved."""

    rule: str
    message: str
    terms: tuple[str, ...]

    def __str__(self) -> str:
        return f"{self.rule}: {self.message}"


def clashes(engine: Engine) -> list[Clash]:
    """Every violation of an OWL 2 RL inconsistency rule in the engine's facts, sorted.

    Literal-subject facts are internal to the engine and take part like any other fact.
    """
    found = set(_clashes(engine))
    return sorted(found, key=lambda clash: (clash.rule, clash.terms))


def _members(engine: Engine, term: str) -> set[str]:
    return {x for x in engine.subjects(TYPE, term) if not x.startswith('"')}


def _common(engine: Engine, c1: str, c2: str) -> list[str]:
    """The individuals (not literals) in both classes, sorted."""
    both = engine.subjects(TYPE, c1) & engine.subjects(TYPE, c2)
    return sorted(x for x in both if not x.startswith('"'))


def _pairs(engine: Engine, p: str) -> Iterator[tuple[str, str]]:
    for s, objects in engine.sp.get(p, {}).items():
        for o in objects:
            yield s, o


def _clashes(e: Engine) -> Iterator[Clash]:
    for x in sorted(_members(e, NOTHING)):  # cls-nothing2
        yield Clash("cls-nothing2", f"{x} is a member of owl:Nothing", (x,))
    for c1, c2 in _pairs(e, DISJOINT_WITH):  # cax-dw
        for x in _common(e, c1, c2):
            yield Clash(
                "cax-dw",
                f"{x} is a member of the disjoint classes {c1} and {c2}",
                (x, *sorted((c1, c2))),
            )
    for axiom in e.subjects(TYPE, ALL_DISJOINT_CLASSES):  # cax-adc
        for head in e.objects(axiom, MEMBERS):
            for c1, c2 in combinations(e.list_items(head), 2):
                for x in _common(e, c1, c2):
                    yield Clash(
                        "cax-adc",
                        f"{x} is a member of the disjoint classes {c1} and {c2}",
                        (x, *sorted((c1, c2))),
                    )
    for c1, c2 in _pairs(e, COMPLEMENT_OF):  # cls-com
        for x in _common(e, c1, c2):
            yield Clash(
                "cls-com", f"{x} is a member of {c1} and of its complement {c2}", (x, c1, c2)
            )
    for x, y in _pairs(e, DIFFERENT_FROM):  # eq-diff1 (x owl:sameAs x holds for every x)
        if x == y or y in e.objects(x, SAME_AS):
            yield Clash(
                "eq-diff1", f"{x} and {y} are both the same and different", tuple(sorted((x, y)))
            )
    for axiom in e.subjects(TYPE, ALL_DIFFERENT):  # eq-diff2, eq-diff3
        for list_predicate, rule in ((MEMBERS, "eq-diff2"), (DISTINCT_MEMBERS, "eq-diff3")):
            for head in e.objects(axiom, list_predicate):
                for xs, ys in combinations(e.list_positions(head), 2):
                    for x, y in sorted((x, y) for x in xs for y in ys):
                        if x == y or y in e.objects(x, SAME_AS):
                            yield Clash(
                                rule,
                                f"{x} and {y} are declared all-different but are the same",
                                tuple(sorted((x, y))),
                            )
    for p in e.subjects(TYPE, IRREFLEXIVE):  # prp-irp
        for x, y in _pairs(e, p):
            if x == y:
                yield Clash("prp-irp", f"{x} is related to itself by irreflexive {p}", (x, p))
    for p in e.subjects(TYPE, ASYMMETRIC):  # prp-asyp
        for x, y in _pairs(e, p):
            if x in e.objects(y, p):
                yield Clash(
                    "prp-asyp",
                    f"{x} and {y} are related both ways by asymmetric {p}",
                    (*sorted((x, y)), p),
                )
    for p1, p2 in _pairs(e, PROPERTY_DISJOINT_WITH):  # prp-pdw
        yield from _shared_pairs(e, "prp-pdw", p1, p2)
    for axiom in e.subjects(TYPE, ALL_DISJOINT_PROPERTIES):  # prp-adp
        for head in e.objects(axiom, MEMBERS):
            # Positions, not distinct items: a property listed twice is disjoint with itself.
            for ps1, ps2 in combinations(e.list_positions(head), 2):
                for p1, p2 in sorted((p1, p2) for p1 in ps1 for p2 in ps2):
                    yield from _shared_pairs(e, "prp-adp", p1, p2)
    # prp-npa1/2 match on the three properties alone; the owl:NegativePropertyAssertion type is
    # not part of the rule's body.
    for npa in list(e.sp.get(SOURCE_INDIVIDUAL, {})):
        for x in e.objects(npa, SOURCE_INDIVIDUAL):
            for p in e.objects(npa, ASSERTION_PROPERTY):
                for target, rule in ((TARGET_INDIVIDUAL, "prp-npa1"), (TARGET_VALUE, "prp-npa2")):
                    for y in e.objects(npa, target):
                        if y in e.objects(x, p):
                            yield Clash(
                                rule, f"{x} {p} {y} holds but is asserted not to", (x, p, y)
                            )
    yield from _max_zero(e)
    yield from _datatype_clashes(e)


def _datatype_clashes(e: Engine) -> Iterator[Clash]:
    """dt-not-type (an ill-typed literal, or a literal typed with a datatype that cannot hold its
    value) and dt-diff (two literals with different values that are the same). The engine
    notes each as the fact appears, so this reads three small sets."""
    for x in e.ill_typed:
        yield Clash("dt-not-type", f"{x} is not a valid literal of its datatype", (x,))
    for x, dt in e.mistyped:
        yield Clash("dt-not-type", f"{x} is not a value of the datatype {dt}", (x, dt))
    for x, y in e.unequal_same:
        yield Clash(
            "dt-diff", f"the literals {x} and {y} have different values but are the same", (x, y)
        )


def _shared_pairs(e: Engine, rule: str, p1: str, p2: str) -> Iterator[Clash]:
    for x, y in _pairs(e, p1):
        if y in e.objects(x, p2):
            yield Clash(
                rule,
                f"{x} and {y} are related by the disjoint properties {p1} and {p2}",
                (x, y, *sorted((p1, p2))),
            )


def _max_zero(e: Engine) -> Iterator[Clash]:
    """cls-maxc1, cls-maxqc1, cls-maxqc2: a member of a "max 0" restriction has a value."""
    for predicate, qualified in ((MAX_CARDINALITY, False), (MAX_QUALIFIED_CARDINALITY, True)):
        for r, numbers in e.sp.get(predicate, {}).items():
            if not any(numeric_value(n) == 0 for n in numbers):
                continue
            classes = list(e.objects(r, ON_CLASS)) if qualified else [THING]
            for p in e.objects(r, ON_PROPERTY):
                for u in sorted(_members(e, r)):
                    for y in e.objects(u, p):
                        for c in classes:
                            if c == THING or c in e.objects(y, TYPE):
                                rule = "cls-maxc1"
                                if qualified:
                                    rule = "cls-maxqc2" if c == THING else "cls-maxqc1"
                                yield Clash(
                                    rule,
                                    f"{u} is in {r} (at most 0 {p}) but has {p} {y}",
                                    (u, r, p, y),
                                )
