"""Run conformance cases (premise graph → entailed conclusion graph, or an inconsistent graph)
against the OWL 2 RL engine, in memory, on inputs that never went through the store."""

from collections.abc import Iterable
from pathlib import Path

from pyoxigraph import RdfFormat, parse

from reasoners.owl_rl import closure

Fact = tuple[str, str, str]


def triples(path: Path) -> list[Fact]:
    """The triples of a Turtle or RDF/XML file, as N-Triples terms (blank nodes ``_:…``)."""
    fmt = RdfFormat.TURTLE if path.suffix == ".ttl" else RdfFormat.RDF_XML
    return [
        (str(q.subject), str(q.predicate), str(q.object))
        for q in parse(path=path, format=fmt, base_iri="http://www.example.org/")
    ]


def entails(facts: set[Fact], conclusion: Iterable[Fact]) -> bool:
    """Is every conclusion triple among ``facts``, its blank nodes read as variables?"""
    by_predicate: dict[str, list[Fact]] = {}
    for fact in facts:
        by_predicate.setdefault(fact[1], []).append(fact)
    pattern = sorted(conclusion, key=lambda t: sum(term.startswith("_:") for term in t))

    def match(i: int, binding: dict[str, str]) -> bool:
        if i == len(pattern):
            return True
        s, p, o = (binding.get(t, t) for t in pattern[i])
        for fact in by_predicate.get(p, ()) if not p.startswith("_:") else facts:
            new = dict(binding)
            pairs = zip((s, p, o), fact, strict=True)
            if all(_bind(a, b, new) for a, b in pairs) and match(i + 1, new):
                return True
        return False

    return match(0, {})


def _bind(term: str, value: str, binding: dict[str, str]) -> bool:
    if not term.startswith("_:"):
        return term == value
    bound = binding.setdefault(term, value)
    return bound == value


def passes(premise: list[Fact], conclusion: list[Fact] | None) -> bool:
    """An entailment case (``conclusion`` given) or an inconsistency case (None)."""
    facts, report = closure(premise)
    if conclusion is None:
        return not report.consistent
    return entails(facts, conclusion)
