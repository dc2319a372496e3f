"""Loading the T-Box: once per version, atomically replaced by a new version."""

from pathlib import Path

import pytest
from pyoxigraph import NamedNode

from kg import Store, ensure_ontology, stored_version
from kg.ontology import file_version
from ontologies import ENGRAM_TTL
from ontologies.vocab import CONE, OWL_CLASS, RDF_TYPE, TBOX


def test_first_load_then_unchanged(empty_store: Store) -> None:
    first = ensure_ontology(empty_store)
    size = len(empty_store)
    second = ensure_ontology(empty_store)
    assert (first.action, second.action) == ("loaded", "unchanged")
    assert len(empty_store) == size == empty_store.graph_sizes()[TBOX.value]
    assert stored_version(empty_store) == first.version


def test_new_version_replaces_the_old_one(store_with_ontology: Store, tmp_path: Path) -> None:
    current = file_version(ENGRAM_TTL)
    edited = ENGRAM_TTL.read_text().replace(
        f"<{current.value}>", "<https://w3id.org/engram/ontology/9.9.9>"
    )
    edited = edited.replace("engram:Cone a owl:Class ;", "engram:Cone a owl:Thing ;")
    path = tmp_path / "engram.ttl"
    path.write_text(edited)
    status = ensure_ontology(store_with_ontology, path)
    assert status.action == "replaced"
    assert status.previous == current
    assert stored_version(store_with_ontology) == NamedNode(
        "https://w3id.org/engram/ontology/9.9.9"
    )
    assert list(store_with_ontology.quads(CONE, RDF_TYPE, OWL_CLASS, TBOX)) == []


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("<http://x/o> a <http://www.w3.org/2002/07/owl#Ontology> .", "0 version IRIs"),
        ("<http://x/a> <http://x/b> <http://x/c> .", "found 0 ontologies"),
    ],
)
def test_ontology_without_one_version_iri_is_refused(
    empty_store: Store, tmp_path: Path, text: str, message: str
) -> None:
    path = tmp_path / "bad.ttl"
    path.write_text(text)
    with pytest.raises(ValueError, match=message):
        ensure_ontology(empty_store, path)
    assert len(empty_store) == 0


def test_malformed_ontology_file_changes_nothing(
    store_with_ontology: Store, tmp_path: Path
) -> None:
    path = tmp_path / "broken.ttl"
    path.write_text(ENGRAM_TTL.read_text().replace("0.2.2>", "0.3.0>") + "\nengram:oops .")
    before = len(store_with_ontology)
    with pytest.raises(SyntaxError):
        ensure_ontology(store_with_ontology, path)
    assert len(store_with_ontology) == before
