"""The schema side of the OWL 2 RL rules: T-Box rules, and what instance rules need to know.

- :func:`process_schema` runs the ``scm-*`` rules (and cls-oo, prp-spo2 over whole chains in
  :func:`schema_pass`) when a schema fact appears; the rules that pair two restrictions or read
  RDF lists are evaluated naively over the T-Box by :func:`schema_pass`, which is small.
- :func:`property_info` and :func:`class_info` gather, once per schema state, what the instance
  rules need about one property or one class (its domains, super-classes, restrictions...).
- :func:`touched` names the classes and properties whose instance facts may join with a new
  schema fact, so that an incremental run can process those facts again.
"""

from collections.abc import Iterator
from dataclasses import dataclass
from typing import TYPE_CHECKING

from reasoners.owl_rl._terms import (
    ALL_VALUES_FROM,
    CLASS,
    DATATYPE_PROPERTY,
    DISTINCT_MEMBERS,
    DOMAIN,
    EQUIVALENT_CLASS,
    EQUIVALENT_PROPERTY,
    FIRST,
    FUNCTIONAL,
    HAS_VALUE,
    INTERSECTION_OF,
    INVERSE_FUNCTIONAL,
    INVERSE_OF,
    MAX_CARDINALITY,
    MAX_QUALIFIED_CARDINALITY,
    MEMBERS,
    NOTHING,
    OBJECT_PROPERTY,
    ON_CLASS,
    ON_PROPERTY,
    ONE_OF,
    PROPERTY,
    PROPERTY_CHAIN,
    RANGE,
    REST,
    SOME_VALUES_FROM,
    SUB_CLASS_OF,
    SUB_PROPERTY_OF,
    SYMMETRIC,
    THING,
    TRANSITIVE,
    TYPE,
    UNION_OF,
    numeric_value,
)

if TYPE_CHECKING:
    from reasoners.owl_rl.engine import Engine

__all__ = [
    "ClassInfo",
    "PropertyInfo",
    "class_info",
    "list_owners",
    "process_schema",
    "property_info",
    "schema_pass",
    "touched",
]

LIST_OWNERS = (INTERSECTION_OF, UNION_OF, ONE_OF, PROPERTY_CHAIN, MEMBERS, DISTINCT_MEMBERS)


@dataclass(slots=True)
class PropertyInfo:
    """What the schema says about one property, for the rules on its facts."""

    domains: tuple[str, ...] = ()
    ranges: tuple[str, ...] = ()
    supers: tuple[str, ...] = ()  # prp-spo1, prp-eqp1/2
    inverses: tuple[str, ...] = ()  # prp-inv1/2
    symmetric: bool = False
    transitive: bool = False
    functional: bool = False
    inverse_functional: bool = False
    # (restriction, kind, argument): kind in "svf", "avf", "hv", "max1"
    restrictions: tuple[tuple[str, str, str | None], ...] = ()
    # (chain property, chain, position of this property in the chain)
    chains: tuple[tuple[str, tuple[str, ...], int], ...] = ()
    active: bool = False  # does any rule apply to this property's facts?


@dataclass(slots=True)
class ClassInfo:
    """What the schema says about one class, for the rules on its members."""

    supers: tuple[str, ...] = ()  # cax-sco, cax-eqc1/2
    parts: tuple[str, ...] = ()  # cls-int2: the members of its intersections
    in_intersections: tuple[tuple[str, tuple[str, ...]], ...] = ()  # cls-int1
    in_unions: tuple[str, ...] = ()  # cls-uni
    filler_of: tuple[tuple[str, str], ...] = ()  # cls-svf1 backwards: (restriction, property)
    all_values: tuple[tuple[str, str], ...] = ()  # cls-avf: (property, class)
    has_values: tuple[tuple[str, str], ...] = ()  # cls-hv1: (property, value)
    max_one: tuple[tuple[str, str | None], ...] = ()  # cls-maxc2/maxqc3-4: (property, class)
    max_one_class_of: tuple[tuple[str, str], ...] = ()  # maxqc3 from the value side
    more: bool = False  # does any rule but cax-sco / cax-eqc apply to this class's members?
    quiet_supers: frozenset[str] | None = None  # supers with no rule of their own (lazily)
    loud_supers: tuple[str, ...] = ()


def process_schema(engine: "Engine", s: str, p: str, o: str) -> None:
    add = engine.add
    if p == TYPE:
        if o == CLASS:  # scm-cls
            add(s, SUB_CLASS_OF, s)
            add(s, EQUIVALENT_CLASS, s)
            add(s, SUB_CLASS_OF, THING)
            add(NOTHING, SUB_CLASS_OF, s)
        elif o in (OBJECT_PROPERTY, DATATYPE_PROPERTY, PROPERTY):  # scm-op, scm-dp
            add(s, SUB_PROPERTY_OF, s)
            add(s, EQUIVALENT_PROPERTY, s)
    elif p == SUB_CLASS_OF:
        if s != o:  # scm-sco, from either premise
            for c3 in list(engine.objects(o, SUB_CLASS_OF)):
                if c3 != s:
                    add(s, SUB_CLASS_OF, c3)
            for c0 in list(engine.subjects(SUB_CLASS_OF, s)):
                if c0 != o:
                    add(c0, SUB_CLASS_OF, o)
            for prop in list(engine.subjects(DOMAIN, s)):  # scm-dom1
                add(prop, DOMAIN, o)
            for prop in list(engine.subjects(RANGE, s)):  # scm-rng1
                add(prop, RANGE, o)
        if s in engine.objects(o, SUB_CLASS_OF):  # scm-eqc2
            add(s, EQUIVALENT_CLASS, o)
            add(o, EQUIVALENT_CLASS, s)
    elif p == EQUIVALENT_CLASS:
        if s != o:  # scm-eqc1
            add(s, SUB_CLASS_OF, o)
            add(o, SUB_CLASS_OF, s)
    elif p == SUB_PROPERTY_OF:
        if s != o:  # scm-spo, scm-eqp2, scm-dom2, scm-rng2
            for p3 in list(engine.objects(o, SUB_PROPERTY_OF)):
                if p3 != s:
                    add(s, SUB_PROPERTY_OF, p3)
            for p0 in list(engine.subjects(SUB_PROPERTY_OF, s)):
                if p0 != o:
                    add(p0, SUB_PROPERTY_OF, o)
            if s in engine.objects(o, SUB_PROPERTY_OF):
                add(s, EQUIVALENT_PROPERTY, o)
                add(o, EQUIVALENT_PROPERTY, s)
            for c in list(engine.objects(o, DOMAIN)):
                add(s, DOMAIN, c)
            for c in list(engine.objects(o, RANGE)):
                add(s, RANGE, c)
    elif p == EQUIVALENT_PROPERTY:
        if s != o:  # scm-eqp1
            add(s, SUB_PROPERTY_OF, o)
            add(o, SUB_PROPERTY_OF, s)
    elif p in (DOMAIN, RANGE):
        for c2 in list(engine.objects(o, SUB_CLASS_OF)):  # scm-dom1, scm-rng1
            if c2 != o:
                add(s, p, c2)
        for p1 in list(engine.subjects(SUB_PROPERTY_OF, s)):  # scm-dom2, scm-rng2
            if p1 != s:
                add(p1, p, o)
    if engine.instances_processed:
        engine.requeue(touched(engine, s, p, o))
    engine.queue.append((s, p, o))  # the instance rules apply to schema facts too


def schema_pass(engine: "Engine") -> None:
    """The schema rules over lists and restriction pairs, evaluated naively on the T-Box."""
    add = engine.add
    for c, head in list(_pairs(engine, INTERSECTION_OF)):  # scm-int
        for part in engine.list_items(head):
            add(c, SUB_CLASS_OF, part)
    for c, head in list(_pairs(engine, UNION_OF)):  # scm-uni
        for part in engine.list_items(head):
            add(part, SUB_CLASS_OF, c)
    for c, head in list(_pairs(engine, ONE_OF)):  # cls-oo
        for member in engine.list_items(head):
            add(member, TYPE, c)
    for prop, head in list(_pairs(engine, PROPERTY_CHAIN)):  # prp-spo2, whole chains
        chain = tuple(engine.list_items(head))
        if chain:
            for start in list(engine.sp.get(chain[0], {})):
                for end in engine.walk(start, chain):
                    add(start, prop, end)
    on_property = engine.sp.get(ON_PROPERTY, {})
    for filler_predicate, rules in (
        (SOME_VALUES_FROM, ("scm-svf1", "scm-svf2")),
        (ALL_VALUES_FROM, ("scm-avf1", "scm-avf2")),
        (HAS_VALUE, ("", "scm-hv")),
    ):
        restrictions = list(engine.sp.get(filler_predicate, {}).items())
        for c1, fillers1 in restrictions:
            for c2, fillers2 in restrictions:
                for p1 in list(on_property.get(c1, ())):
                    for p2 in list(on_property.get(c2, ())):
                        _restriction_pair(
                            engine, rules, c1, c2, p1, p2, list(fillers1), list(fillers2)
                        )


def _restriction_pair(
    engine: "Engine",
    rules: tuple[str, str],
    c1: str,
    c2: str,
    p1: str,
    p2: str,
    fillers1: list[str],
    fillers2: list[str],
) -> None:
    same_filler_rule, sub_property_rule = rules
    if same_filler_rule and p1 == p2:  # scm-svf1 / scm-avf1: fillers in a subclass relation
        for y1 in fillers1:
            for y2 in fillers2:
                if y2 in engine.objects(y1, SUB_CLASS_OF):
                    engine.add(c1, SUB_CLASS_OF, c2)
    if p2 in engine.objects(p1, SUB_PROPERTY_OF) and set(fillers1) & set(fillers2):
        if sub_property_rule == "scm-avf2":  # scm-avf2 reverses the direction
            engine.add(c2, SUB_CLASS_OF, c1)
        else:  # scm-svf2, scm-hv
            engine.add(c1, SUB_CLASS_OF, c2)


def _pairs(engine: "Engine", p: str) -> Iterator[tuple[str, str]]:
    for s, objects in engine.sp.get(p, {}).items():
        for o in objects:
            yield s, o


def list_owners(engine: "Engine", node: str) -> set[str]:
    """The terms whose list holds ``node`` (an intersection class, a chain property...)."""
    heads, frontier = {node}, [node]
    while frontier:
        for previous in engine.subjects(REST, frontier.pop()):
            if previous not in heads:
                heads.add(previous)
                frontier.append(previous)
    return {owner for head in heads for p in LIST_OWNERS for owner in engine.subjects(p, head)}


def touched(engine: "Engine", s: str, p: str, o: str) -> set[str]:
    """Classes and properties whose facts may join with a new schema fact."""
    touched = {s, o}
    if p in (FIRST, REST):
        touched = set()
        for owner in list_owners(engine, s):
            touched.add(owner)
            for q in LIST_OWNERS:
                for head in engine.objects(owner, q):
                    touched.update(engine.list_items(head))
    for term in list(touched):
        touched.update(engine.objects(term, ON_PROPERTY))
        touched.update(engine.objects(term, SOME_VALUES_FROM))
        touched.update(engine.objects(term, ALL_VALUES_FROM))
        touched.update(engine.objects(term, ON_CLASS))
        touched.update(engine.subjects(ON_PROPERTY, term))
    return touched


def property_info(engine: "Engine", p: str) -> PropertyInfo:
    characteristics = engine.objects(p, TYPE)
    supers = (engine.objects(p, SUB_PROPERTY_OF) | engine.objects(p, EQUIVALENT_PROPERTY)) | set(
        engine.subjects(EQUIVALENT_PROPERTY, p)
    )
    restrictions: list[tuple[str, str, str | None]] = []
    for r in engine.subjects(ON_PROPERTY, p):
        restrictions += [(r, "svf", y) for y in engine.objects(r, SOME_VALUES_FROM)]
        restrictions += [(r, "avf", y) for y in engine.objects(r, ALL_VALUES_FROM)]
        restrictions += [(r, "hv", y) for y in engine.objects(r, HAS_VALUE)]
        restrictions += [(r, "max1", c) for c in max_one_classes(engine, r)]
    chains = []
    for node in engine.subjects(FIRST, p):
        for owner in list_owners(engine, node):
            for head in engine.objects(owner, PROPERTY_CHAIN):
                chain = tuple(engine.list_items(head))
                chains += [(owner, chain, i) for i, q in enumerate(chain) if q == p]
    info = PropertyInfo(
        domains=tuple(engine.objects(p, DOMAIN)),
        ranges=tuple(engine.objects(p, RANGE)),
        supers=tuple(supers - {p}),
        inverses=tuple(engine.objects(p, INVERSE_OF) | engine.subjects(INVERSE_OF, p)),
        symmetric=SYMMETRIC in characteristics,
        transitive=TRANSITIVE in characteristics,
        functional=FUNCTIONAL in characteristics,
        inverse_functional=INVERSE_FUNCTIONAL in characteristics,
        restrictions=tuple(restrictions),
        chains=tuple(set(chains)),
    )
    info.active = bool(
        info.domains
        or info.ranges
        or info.supers
        or info.inverses
        or info.symmetric
        or info.transitive
        or info.functional
        or info.inverse_functional
        or info.restrictions
        or info.chains
    )
    engine.property_cache[p] = info
    return info


def max_one_classes(engine: "Engine", r: str) -> list[str | None]:
    """[None] for ``maxCardinality 1``, [C] for ``maxQualifiedCardinality 1 onClass C``."""
    result: list[str | None] = []
    if any(numeric_value(n) == 1 for n in engine.objects(r, MAX_CARDINALITY)):
        result.append(None)
    if any(numeric_value(n) == 1 for n in engine.objects(r, MAX_QUALIFIED_CARDINALITY)):
        result += list(engine.objects(r, ON_CLASS))
    return result


def class_info(engine: "Engine", c: str) -> ClassInfo:
    supers = (
        set(engine.objects(c, SUB_CLASS_OF))
        | engine.objects(c, EQUIVALENT_CLASS)
        | engine.subjects(EQUIVALENT_CLASS, c)
    )
    parts = [
        part for head in engine.objects(c, INTERSECTION_OF) for part in engine.list_items(head)
    ]
    in_intersections, in_unions = [], []
    for node in engine.subjects(FIRST, c):
        for owner in list_owners(engine, node):
            for head in engine.objects(owner, INTERSECTION_OF):
                items = engine.list_items(head)
                if c in items:
                    in_intersections.append((owner, tuple(items)))
            for head in engine.objects(owner, UNION_OF):
                if c in engine.list_items(head):
                    in_unions.append(owner)
    properties = engine.objects(c, ON_PROPERTY)
    info = ClassInfo(
        supers=tuple(supers - {c}),
        parts=tuple(parts),
        in_intersections=tuple(set(in_intersections)),
        in_unions=tuple(set(in_unions)),
        filler_of=tuple(
            (r, prop)
            for r in engine.subjects(SOME_VALUES_FROM, c)
            for prop in engine.objects(r, ON_PROPERTY)
        ),
        all_values=tuple(
            (prop, y) for prop in properties for y in engine.objects(c, ALL_VALUES_FROM)
        ),
        has_values=tuple((prop, y) for prop in properties for y in engine.objects(c, HAS_VALUE)),
        max_one=tuple((prop, k) for prop in properties for k in max_one_classes(engine, c)),
        max_one_class_of=tuple(
            (r, prop)
            for r in engine.subjects(ON_CLASS, c)
            if c in max_one_classes(engine, r)
            for prop in engine.objects(r, ON_PROPERTY)
        ),
    )
    info.more = bool(
        info.parts
        or info.in_intersections
        or info.in_unions
        or info.filler_of
        or info.all_values
        or info.has_values
        or info.max_one
        or info.max_one_class_of
    )
    engine.class_cache[c] = info
    return info
