"""Answers that differ from ARMOR's unless the store keeps literal datatypes, SWRL sees
``disj_inds_of_class``, and names print as ARMOR prints them (docs/armor-differences in the
README's ARMOR section)."""

from collections.abc import Callable
from pathlib import Path

from .conftest import Armor

LONG = '"1665579740"^^xsd:long'
SPARQL_VALUE = "SELECT ?v WHERE { ?i <http://ex.org/%s#stamp> ?v }"


def test_long_values_stay_long_in_queries_sparql_and_save(
    armor: Armor, loaded: Callable[..., str], tmp_path: Path
) -> None:
    ref = loaded()
    assert armor.call("ADD", "DATAPROP", "IND", ["stamp", "r", "LONG", "1665579740"], ref=ref)[
        "success"
    ]
    sparql = armor.call("QUERY", "SPARQL", "", [SPARQL_VALUE % ref], ref=ref)
    assert sparql["queried_objects"] == ["{v=1665579740^^http://www.w3.org/2001/XMLSchema#long}"]
    saved = tmp_path / "saved.ttl"
    assert armor.call("SAVE", "", "", [str(saved)], ref=ref)["success"]
    assert '"1665579740"^^xsd:long' in saved.read_text()


def test_long_values_of_a_loaded_file_stay_long(armor: Armor, ref: str, tmp_path: Path) -> None:
    source = tmp_path / "onto.ttl"
    iri = "http://ex.org/loaded"
    source.write_text(
        f"@prefix : <{iri}#> . @prefix xsd: <http://www.w3.org/2001/XMLSchema#> . "
        "@prefix owl: <http://www.w3.org/2002/07/owl#> . "
        f"<{iri}> a owl:Ontology . :stamp a owl:DatatypeProperty . "
        ':r a owl:NamedIndividual ; :stamp "1665579740"^^xsd:long ; :age "7"^^xsd:byte .'
    )
    loaded = armor.call("LOAD", "FILE", "", [str(source), iri, "false", "PELLET", "false"], ref=ref)
    assert loaded["success"], loaded
    stamp = armor.call("QUERY", "DATAPROP", "IND", ["stamp", "r"], ref=ref)["queried_objects"]
    age = armor.call("QUERY", "DATAPROP", "IND", ["age", "r"], ref=ref)["queried_objects"]
    assert (stamp, age) == ([LONG], ['"7"^^xsd:byte'])
