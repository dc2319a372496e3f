"""A retraction re-derived within the part of the closure it can touch, not the whole closure.

OWL 2 RL has no cheap retraction in general (a triple may be derived several ways, and schema
triples reach everything), but most retractions are instance triples, and outside equality
(``owl:sameAs``) and SWRL every instance rule joins facts about terms linked by the facts
themselves: ``prp-trp`` links ``x`` to ``z`` through ``y``, ``cls-svf1`` the owner to its value,
``cls-hv1`` concludes an edge that is then in the closure. A type triple ``x rdf:type C`` links
nothing (``C`` is a class, whose rules are schema). So the closure splits into *regions*: sets
of individuals connected by the closure's non-type triples, each region's facts derived only
from its own asserted facts and the schema.

:func:`retract` finds the region of the retracted triples (a walk from their terms over the
closure's indexes), removes every fact about it from the engine, puts back the region's
asserted triples that remain (and any newly asserted ones), and lets the engine derive their
consequences again (semi-naive, as after an addition). The rest of the closure is left as it
is: by the locality above, none of it depended on the region. The cost is that of the region,
not of the ontology.

It declines (returns None, the engine untouched) whenever that argument might not hold, and the
caller then recomputes the whole closure: a retracted or added triple of the schema or of a SWRL
rule, equality anywhere in the closure, SWRL rules at all, a region that holds a class, a
property, a schema node or an axiom's term (punning), a literal whose types depend on the
triples that use it, or a region larger than ``limit`` terms.

Typed literals are leaves unless they are the subject of a non-type fact: their types
(``dt-type2``: the datatype and its supertypes) depend on nothing else, so two regions sharing
``"0"^^xsd:integer`` stay two regions.

>>> from reasoners.owl_rl.engine import Engine
>>> from ontologies.vocab import RDF_NS, RDFS_NS
>>> t, sco = f"<{RDF_NS}type>", f"<{RDFS_NS}subClassOf>"
>>> engine = Engine()
>>> engine.add_all([("<A>", sco, "<B>"), ("<a1>", t, "<A>"), ("<a2>", t, "<A>")])
>>> engine.run()
>>> asserted = {("<A>", sco, "<B>"), ("<a1>", t, "<A>")}  # a2's type was retracted
>>> change = retract(engine, asserted, removed=[("<a2>", t, "<A>")], added=[], limit=100)
>>> sorted(change.removed), change.added
([('<a2>', '<http://www.w3.org/1999/02/22-rdf-syntax-ns#type>', '<A>'), \
('<a2>', '<http://www.w3.org/1999/02/22-rdf-syntax-ns#type>', '<B>')], [])
"""

from collections.abc import Iterable
from dataclasses import dataclass

from ontologies.vocab import SWRL_NS
from reasoners.owl_rl._terms import HAS_KEY, SAME_AS, TYPE
from reasoners.owl_rl.datatypes import value_types
from reasoners.owl_rl.engine import AXIOMS, SCHEMA_PREDICATES, SCHEMA_TYPES, Engine, Fact

__all__ = ["Retraction", "inferred_delta", "retract"]

_AXIOM_TERMS = frozenset(term for fact in AXIOMS for term in fact)
_SWRL_PREFIX = f"<{SWRL_NS}"


@dataclass(frozen=True)
class Retraction:
    """What one scoped retraction changed in the closure.

    ``removed`` / ``added``: closure facts (literal subjects and asserted ones included) that
    left / joined it; ``region``: the number of terms whose facts were derived again.
    """

    removed: list[Fact]
    added: list[Fact]
    region: int


def retract(
    engine: Engine,
    asserted: set[Fact],
    *,
    removed: list[Fact],
    added: list[Fact],
    limit: int,
) -> Retraction | None:
    """Bring ``engine`` (the closure of the old asserted set) to the closure of ``asserted``
    (the new one: the old less ``removed``, plus ``added``) by re-deriving the retracted
    triples' region only; None if that is not known to be exact (then nothing was touched).

    ``removed`` and ``added`` must be exactly the difference between the two asserted sets.
    """
    if engine.fact_hooks or engine.sp.get(SAME_AS):
        return None
    if any(_schema_or_swrl(fact) for fact in (*removed, *added)):
        return None
    seeds = [s for s, _, _ in removed]
    seeds += [o for _, p, o in removed if p != TYPE]
    region = _region(engine, seeds, limit)
    if region is None:
        return None
    gone = _remove_region(engine, region)
    gone_set = set(gone)
    engine.take_log()
    engine.add_all(fact for fact in gone if fact in asserted)
    engine.add_all(added)
    engine.run()
    new = engine.take_log()
    new_set = set(new)
    return Retraction(
        removed=[fact for fact in gone if fact not in new_set],
        added=[fact for fact in new if fact not in gone_set],
        region=len(region),
    )


def inferred_delta(
    engine: Engine,
    asserted: set[Fact],
    change: Retraction,
    *,
    removed: set[Fact],
    added: set[Fact],
) -> tuple[list[Fact], list[Fact]]:
    """The inferred graph's (additions, deletions) after :func:`retract`: closure facts that
    are not asserted, literal subjects left out. ``asserted`` is the new asserted set,
    ``removed`` / ``added`` what it lost / gained."""

    def was_asserted(fact: Fact) -> bool:
        return fact in removed or (fact in asserted and fact not in added)

    to_remove = [f for f in change.removed if f[0][0] != '"' and not was_asserted(f)]
    to_remove += [f for f in added if f in engine and f not in change.added]  # now asserted
    to_add = [f for f in change.added if f[0][0] != '"' and f not in asserted]
    to_add += [f for f in removed if f in engine]  # no longer asserted, still entailed
    return to_add, to_remove


def _schema_or_swrl(fact: Fact) -> bool:
    _, p, o = fact
    if p in SCHEMA_PREDICATES or (p == TYPE and o in SCHEMA_TYPES):
        return True
    return p == HAS_KEY or p.startswith(_SWRL_PREFIX) or o.startswith(_SWRL_PREFIX)


def _region(engine: Engine, seeds: Iterable[str], limit: int) -> set[str] | None:
    """The terms linked to ``seeds`` by non-type facts of the closure (leaf literals left out);
    None if one of them is not a plain individual, or if there are more than ``limit``."""
    sp, op = engine.sp, engine.op
    instance_sp = [(p, index) for p, index in sp.items() if p != TYPE]
    instance_op = [(p, index) for p, index in op.items() if p != TYPE]
    classes = op.get(TYPE, {})
    types = sp.get(TYPE, {})
    schema_sp = [sp[p] for p in SCHEMA_PREDICATES if p in sp]
    schema_op = [op[p] for p in SCHEMA_PREDICATES if p in op]
    region: set[str] = set()
    todo = list(dict.fromkeys(seeds))
    while todo:
        term = todo.pop()
        if term in region:
            continue
        linked_forward = [o for _, index in instance_sp for o in index.get(term, ())]
        if term[0] == '"' and not linked_forward:  # a leaf literal
            if not _only_datatype_types(term, types.get(term, ())):
                return None
            continue
        if (
            term in sp
            or term in classes
            or term in _AXIOM_TERMS
            or term.startswith(_SWRL_PREFIX)
            or any(term in index for index in schema_sp)
            or any(term in index for index in schema_op)
            or not SCHEMA_TYPES.isdisjoint(types.get(term, ()))
        ):
            return None  # a class, a property or a schema node: its rules reach everywhere
        region.add(term)
        if len(region) > limit:
            return None
        todo.extend(o for o in linked_forward if o not in region)
        todo.extend(s for _, index in instance_op for s in index.get(term, ()) if s not in region)
    return region


def _only_datatype_types(literal: str, types: Iterable[str]) -> bool:
    """Does the literal have only the types ``dt-type2`` gives it (which depend on nothing)?"""
    return set(types) <= value_types(literal)


def _remove_region(engine: Engine, region: set[str]) -> list[Fact]:
    """Take every fact whose subject is in ``region`` out of the engine's indexes; return them.

    Every fact about the region has its subject there (a non-type fact links its object to it;
    a type fact's object is a class, never in a region).
    """
    gone: list[Fact] = []
    sp, op = engine.sp, engine.op
    for p, by_subject in sp.items():
        by_object = op[p]
        for s in [term for term in region if term in by_subject]:
            for o in by_subject.pop(s):
                gone.append((s, p, o))
                subjects = by_object[o]
                subjects.discard(s)
                if not subjects:
                    del by_object[o]
    engine.untype_literals(term for term in region if term[0] == '"')
    return gone
