"""The terms the fleet writes (kg.remote's journal and lease, episodes.archive's objects) are
declared in the Engram T-Box, as every Engram term is."""

import pytest
import rdflib
from rdflib.namespace import OWL, RDF, RDFS

from ontologies import ENGRAM_TTL, vocab

FLEET_TERMS = {
    "JOURNAL_ENTRY": OWL.Class,
    "REVISION": OWL.DatatypeProperty,
    "COMMITTED_AT": OWL.DatatypeProperty,
    "TOUCHED": OWL.ObjectProperty,
    "TOUCHED_EVERYTHING": OWL.DatatypeProperty,
    "LEASE_HOLDER": OWL.DatatypeProperty,
    "LEASE_EXPIRES": OWL.DatatypeProperty,
    "STREAM_OBJECT": OWL.ObjectProperty,
    "BYTE_SIZE": OWL.DatatypeProperty,
    "SHA256": OWL.DatatypeProperty,
}


@pytest.fixture(scope="module")
def tbox() -> rdflib.Graph:
    graph = rdflib.Graph()
    graph.parse(ENGRAM_TTL, format="turtle")
    return graph


@pytest.mark.parametrize("name", sorted(FLEET_TERMS))
def test_each_fleet_term_is_declared_labelled_and_commented(tbox: rdflib.Graph, name: str) -> None:
    term = rdflib.URIRef(getattr(vocab, name).value)
    assert (term, RDF.type, FLEET_TERMS[name]) in tbox
    assert (term, RDFS.label, None) in tbox
    assert (term, RDFS.comment, None) in tbox
