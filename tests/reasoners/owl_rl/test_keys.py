"""prp-key: ``owl:hasKey`` makes individuals with the same key values the same."""

from pyoxigraph import RdfFormat

from reasoners.owl_rl import materialise

from .conftest import ASSERTED, INFERRED, Loader, graph_triples
from .test_owlrl_parity import PREFIXES

EX = "http://example.org/"
SAME = "<http://www.w3.org/2002/07/owl#sameAs>"
KEYED = ":Robot owl:hasKey ( :maker :serial ) . :maker a owl:ObjectProperty .\n"


def test_individuals_sharing_every_key_value_are_the_same(load: Loader) -> None:
    store = load(
        PREFIXES
        + KEYED
        + """:r1 a :Robot ; :maker :acme ; :serial "A7" ; :charge 80 .
        :r2 a :Robot ; :maker :acme ; :serial "A7" .
        :r3 a :Robot ; :maker :other ; :serial "A7" .
        :r4 :maker :acme ; :serial "A7" ."""
    )
    materialise(store, asserted=ASSERTED, inferred=INFERRED)
    inferred = graph_triples(store)
    assert f"<{EX}r1> {SAME} <{EX}r2>" in inferred
    assert (
        f"<{EX}r2> <{EX}charge> " + '"80"^^<http://www.w3.org/2001/XMLSchema#integer>' in inferred
    )
    assert not any(f"<{EX}r3>" in t and SAME in t for t in inferred)  # another maker
    assert not any(f"<{EX}r4>" in t and SAME in t for t in inferred)  # not a Robot


def test_a_key_added_by_a_later_reason_applies(load: Loader) -> None:
    store = load(
        PREFIXES + ':r1 a :Robot ; :maker :acme ; :serial "A7" . :r2 a :Robot ; '
        ':maker :acme ; :serial "A7" .'
    )
    materialise(store, asserted=ASSERTED, inferred=INFERRED)
    assert not any(SAME in t for t in graph_triples(store))
    with store.transaction() as tx:
        tx.load(PREFIXES + KEYED, format=RdfFormat.TURTLE, graph=ASSERTED)
    materialise(store, asserted=ASSERTED, inferred=INFERRED)
    assert f"<{EX}r1> {SAME} <{EX}r2>" in graph_triples(store)
