"""Helpers for the OWL 2 RL tests: load a reference, read what REASON wrote, ask owlrl."""

import textwrap
from collections.abc import Callable

import owlrl
import pytest
import rdflib
from owlrl.AxiomaticTriples import OWLRL_Datatypes_Disjointness
from pyoxigraph import NamedNode, RdfFormat, parse
from rdflib.namespace import OWL

from kg import Store
from ontologies.vocab import reference_graph
from reasoners.owl_rl import materialise

ASSERTED = reference_graph("test")
INFERRED = reference_graph("test", inferred=True)
KILLED_REASON = textwrap.dedent(
    """
    import os, signal, sys
    from pyoxigraph import RdfFormat
    from kg import Store
    from ontologies.vocab import reference_graph
    from reasoners.owl_rl import materialise
    from reasoners.owl_rl.synthetic import scene_ontology

    name = sys.argv[2]
    asserted, inferred = reference_graph(name), reference_graph(name, inferred=True)
    store = Store(sys.argv[1])
    with store.transaction() as tx:
        tx.load(
            "\\n".join(scene_ontology(3_000, seed=7)).encode(),
            format=RdfFormat.N_TRIPLES,
            graph=asserted,
        )
    Store._end_bulk_write = lambda self, marker: os.kill(os.getpid(), signal.SIGKILL)
    materialise(store, asserted=asserted, inferred=inferred)
    print("not killed", flush=True)
    """
)
"""A script (store path, reference name) that loads a 3k-triple scene ontology and is killed
between the bulk load of its full REASON and the end of that write."""
Loader = Callable[[str | bytes, RdfFormat], Store]


@pytest.fixture
def load() -> Loader:
    """Returns a function: document, format -> a new in-memory store holding it in ASSERTED."""

    def _load(document: str | bytes, format: RdfFormat = RdfFormat.TURTLE) -> Store:
        store = Store()
        with store.transaction() as tx:
            tx.load(document, format=format, graph=ASSERTED, base_iri="http://example.org/")
        return store

    return _load


def graph_triples(store: Store, graph: NamedNode = INFERRED) -> set[str]:
    """The triples of a graph, each as an N-Triples line without the final dot."""
    return {f"{q.subject} {q.predicate} {q.object}" for q in store.quads(graph=graph)}


def recomputed(store: Store) -> set[str]:
    """The inferred graph a full REASON gives over a fresh copy of the store's asserted graph."""
    fresh = Store()
    with fresh.transaction() as tx:
        tx.load(store.graph_ntriples(ASSERTED), format=RdfFormat.N_TRIPLES, graph=ASSERTED)
    materialise(fresh, asserted=ASSERTED, inferred=INFERRED)
    return graph_triples(fresh)


def owlrl_inferences(store: Store) -> set[str]:
    """What owlrl (OWLRL_Semantics) adds to the asserted graph, minus the documented noise.

    Filtered, because they are out of scope for a store of RDF triples and for this engine:
    - triples with a literal subject (dt-type2 typing ``"1"^^xsd:integer rdf:type xsd:integer``;
      generalised RDF that Oxigraph cannot store; our engine keeps them internally only),
    - ``x owl:sameAs x`` (eq-ref: true of every term; owlrl emits it for an arbitrary subset),
    - the ``owl:disjointWith`` triples between datatypes owlrl adds (not a rule of the W3C
      tables; the engine checks literals against value spaces instead, dt-not-type),
    - owlrl's own error report (``ErrorMessage`` nodes), compared through is_consistent instead.
    """
    graph = rdflib.Graph()
    graph.parse(data=store.graph_ntriples(ASSERTED), format="nt")
    before = set(graph)
    owlrl.DeductiveClosure(owlrl.OWLRL_Semantics).expand(graph)
    kept = rdflib.Graph()
    error_namespace = "http://www.daml.org/2002/03/agents/agent-ont#"
    for s, p, o in set(graph) - before:
        if isinstance(s, rdflib.Literal | rdflib.BNode):
            continue
        if p == OWL.sameAs and s == o:
            continue
        if (s, p, o) in OWLRL_Datatypes_Disjointness or str(p).startswith(error_namespace):
            continue
        kept.add((s, p, o))
    text = kept.serialize(format="nt", encoding="utf-8")
    return {
        f"{t.subject} {t.predicate} {t.object}" for t in parse(text, format=RdfFormat.N_TRIPLES)
    }
