"""Answers that differ from ARMOR's unless the store keeps literal datatypes and names print as
ARMOR prints them, in SPARQL and SAVE too (the README's ARMOR section). armor_py_api's own calls
for the same differences, and SWRL after ``disj_inds_of_class``, are in test_armor_py_api.py."""

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


def test_floats_print_as_java_prints_them(armor: Armor, loaded: Callable[..., str]) -> None:
    ref = loaded()
    for prop, value in [("a", "2"), ("b", "1e10"), ("c", "0.0001"), ("d", "0.5")]:
        assert armor.call("ADD", "DATAPROP", "IND", [prop, "r", "DOUBLE", value], ref=ref)[
            "success"
        ]
    got = [
        armor.call("QUERY", "DATAPROP", "IND", [prop, "r"], ref=ref)["queried_objects"]
        for prop in "abcd"
    ]
    assert got == [
        ['"2.0"^^xsd:float'],
        ['"1.0E10"^^xsd:float'],
        ['"1.0E-4"^^xsd:float'],
        ['"0.5"^^xsd:float'],
    ]
    sparql = "SELECT ?v WHERE { ?i <http://ex.org/" + ref + "#a> ?v }"
    assert armor.call("QUERY", "SPARQL", "", [sparql], ref=ref)["queried_objects"] == [
        "{v=2.0^^http://www.w3.org/2001/XMLSchema#float}"
    ]


def test_owl_nothing_prints_as_the_owl_api_prints_it(
    armor: Armor, loaded: Callable[..., str]
) -> None:
    ref = loaded()
    assert armor.call("ADD", "CLASS", "", ["Room"], ref=ref)["success"]
    subclasses = armor.call("QUERY", "CLASS", "CLASS", ["Room"], ref=ref)["queried_objects"]
    assert subclasses == ["owl:Nothing"]


def test_a_name_with_a_space_is_accepted_and_printed_as_given(
    armor: Armor, loaded: Callable[..., str]
) -> None:
    ref = loaded()
    added = armor.call("ADD", "IND", "CLASS", ["living room", "Room"], ref=ref)
    assert added["success"], added
    members = armor.call("QUERY", "IND", "CLASS", ["Room"], ref=ref)["queried_objects"]
    assert members == [f"<http://ex.org/{ref}#living room>"]
    short = armor.call("QUERY", "IND", "CLASS", ["Room"], ref=ref, values="short")
    assert short["queried_objects"] == ["living room"]


def test_a_buffered_reasoner_answers_from_the_ontology_as_loaded(
    armor: Armor, ref: str, tmp_path: Path
) -> None:
    source = tmp_path / "rooms.ttl"
    iri = "http://ex.org/rooms"
    source.write_text(
        f"@prefix : <{iri}#> . @prefix owl: <http://www.w3.org/2002/07/owl#> . "
        "@prefix rdfs: <http://www.w3.org/2000/01/rdf-schema#> . "
        f"<{iri}> a owl:Ontology . :Room a owl:Class . :Robot a owl:Class . "
        ":isIn a owl:ObjectProperty ; rdfs:domain :Robot ; rdfs:range :Room . "
        ":r1 a owl:NamedIndividual ; :isIn :k1 . :k1 a owl:NamedIndividual ."
    )
    args = [str(source), iri, "false", "PELLET", "true"]  # buffered reasoner
    assert armor.call("LOAD", "FILE", "", args, ref=ref)["success"]
    members = armor.call("QUERY", "IND", "CLASS", ["Room"], ref=ref)["queried_objects"]
    assert members == [f"<{iri}#k1>"]
