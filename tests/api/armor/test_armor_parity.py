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


RULE = """
@prefix : <{iri}#> . @prefix swrl: <http://www.w3.org/2003/11/swrl#> .
@prefix owl: <http://www.w3.org/2002/07/owl#> .
<{iri}> a owl:Ontology . :Room a owl:Class . :hasDoor a owl:ObjectProperty .
:connectedTo a owl:ObjectProperty .
<urn:swrl:var#r> a swrl:Variable . <urn:swrl:var#s> a swrl:Variable .
<urn:swrl:var#d> a swrl:Variable .
[ a swrl:Imp ;
  swrl:body (
    [ a swrl:IndividualPropertyAtom ; swrl:propertyPredicate :hasDoor ;
      swrl:argument1 <urn:swrl:var#r> ; swrl:argument2 <urn:swrl:var#d> ]
    [ a swrl:IndividualPropertyAtom ; swrl:propertyPredicate :hasDoor ;
      swrl:argument1 <urn:swrl:var#s> ; swrl:argument2 <urn:swrl:var#d> ]
    [ a swrl:DifferentIndividualsAtom ;
      swrl:argument1 <urn:swrl:var#r> ; swrl:argument2 <urn:swrl:var#s> ] ) ;
  swrl:head (
    [ a swrl:IndividualPropertyAtom ; swrl:propertyPredicate :connectedTo ;
      swrl:argument1 <urn:swrl:var#r> ; swrl:argument2 <urn:swrl:var#s> ] ) ] .
"""


def test_swrl_rules_see_the_individuals_disj_inds_of_class_declared_different(
    armor: Armor, ref: str, tmp_path: Path
) -> None:
    """The calls armor_py_api makes for a surveillance map: add_ind_to_class, add_objectprop_to_ind,
    disj_inds_of_class, reason, query.objectprop_b2_ind."""
    iri = "http://ex.org/map"
    source = tmp_path / "map.ttl"
    source.write_text(RULE.format(iri=iri))
    assert armor.call("LOAD", "FILE", "", [str(source), iri, "true", "PELLET", "true"], ref=ref)[
        "success"
    ]
    for room, doors in {"R1": ["D1"], "C1": ["D1", "D2"], "R2": ["D2"]}.items():
        assert armor.call("ADD", "IND", "CLASS", [room, "Room"], ref=ref)["success"]
        for door in doors:
            assert armor.call("ADD", "OBJECTPROP", "IND", ["hasDoor", room, door], ref=ref)[
                "success"
            ]
    assert armor.call("DISJOINT", "IND", "CLASS", ["Room"], ref=ref)["success"]
    assert armor.call("APPLY", "", "", [], ref=ref)["success"]
    assert armor.call("REASON", "", "", [], ref=ref)["success"]
    connected = {
        room: armor.call("QUERY", "OBJECTPROP", "IND", ["connectedTo", room], ref=ref)[
            "queried_objects"
        ]
        for room in ("R1", "C1", "R2")
    }
    assert connected == {
        "R1": [f"<{iri}#C1>"],
        "C1": [f"<{iri}#R1>", f"<{iri}#R2>"],
        "R2": [f"<{iri}#C1>"],
    }
