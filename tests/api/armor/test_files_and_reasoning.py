"""LOAD in every format, SAVE / SAVE INFERENCE, REASON, and the armor_py_api client example."""

from pathlib import Path

import pytest
from pyoxigraph import RdfFormat, parse

from api.armor.owlxml import OwlXmlError, owlxml_triples
from api.client import ArmorClient, ArmorServiceCallError, ArmorServiceInternalError
from tests.api.armor.conftest import DATA, TEST_IRI, Armor

TURTLE = """@prefix : <http://ex.org/t#> . @prefix owl: <http://www.w3.org/2002/07/owl#> .
@prefix rdfs: <http://www.w3.org/2000/01/rdf-schema#> .
<http://ex.org/t> a owl:Ontology . :Kitchen rdfs:subClassOf :Room . :k1 a :Kitchen ."""
NTRIPLES = (
    "<http://ex.org/t#Kitchen> <http://www.w3.org/2000/01/rdf-schema#subClassOf> "
    "<http://ex.org/t#Room> .\n"
    "<http://ex.org/t#k1> <http://www.w3.org/1999/02/22-rdf-syntax-ns#type> "
    "<http://ex.org/t#Kitchen> .\n"
)


@pytest.mark.parametrize(
    ("name", "text"), [("t.ttl", TURTLE), ("t.nt", NTRIPLES), ("t.owl", TURTLE)]
)
def test_load_turtle_and_ntriples(
    armor: Armor, ref: str, tmp_path: Path, name: str, text: str
) -> None:
    path = tmp_path / name
    path.write_text(text)
    assert armor.call(
        "LOAD", "FILE", "", [str(path), "http://ex.org/t", "false", "", "false"], ref=ref
    )["success"]
    assert armor.call("QUERY", "IND", "CLASS", ["Room"], ref=ref, values="short")[
        "queried_objects"
    ] == ["k1"]


@pytest.mark.parametrize("name", ["test.owl", "test.owx"])
def test_load_protege_files_and_reason_the_armor_example(armor: Armor, ref: str, name: str) -> None:
    """armor_py_api's client_test: ind_1 is inferred into
    Class_4 ≡ ∃OProperty_1.Class_3 ⊓ ∃DProperty_1.xsd:integer."""
    client = ArmorClient("client", ref, base_url=armor.url)
    client.utils.load_ref_from_file(str(DATA / name), TEST_IRI, True, "PELLET", True)
    client.manipulation.add_ind_to_class("ind_1", "Class_1")
    client.manipulation.add_ind_to_class("ind_2", "Class_3")
    client.manipulation.add_objectprop_to_ind("OProperty_1", "ind_1", "ind_2")
    client.manipulation.add_dataprop_to_ind("DProperty_1", "ind_1", "INTEGER", "1")
    assert client.query.ind_b2_class("Class_4") == []
    client.utils.apply_buffered_changes()
    assert client.query.ind_b2_class("Class_4") == []  # the buffered reasoner has not run yet
    consistent = client.utils.sync_buffered_reasoner()
    assert client.query.ind_b2_class("Class_4") == ["ind_1"]
    assert client.query.check_ind_exists("ind_1")
    client.manipulation.replace_one_dataprop_b2_ind("DProperty_1", "ind_1", "INTEGER", "3")
    client.utils.apply_buffered_changes()
    assert client.query.dataprop_b2_ind("DProperty_1", "ind_1") == ['"3"^^xsd:integer']
    if name == "test.owx":  # Class_1 and Class_3 are disjoint there, and a SWRL rule types Big
        assert consistent is True
        assert "ind_0" in client.query.ind_b2_class("Big")
        client.manipulation.add_ind_to_class("ind_2", "Class_1")
        assert client.utils.sync_buffered_reasoner() is False
    client.close()


def test_save_writes_asserted_axioms_and_save_inference_adds_inferences_without_asserting(
    armor: Armor, ref: str, tmp_path: Path
) -> None:
    armor.call(
        "LOAD", "FILE", "", [str(DATA / "test.owl"), TEST_IRI, "false", "PELLET", "true"], ref=ref
    )
    for directive in (["ind_1", "Class_2"], ["ind_2", "Class_3"]):
        armor.call("ADD", "IND", "CLASS", directive, ref=ref)
    armor.call("ADD", "OBJECTPROP", "IND", ["OProperty_1", "ind_1", "ind_2"], ref=ref)
    armor.call("ADD", "DATAPROP", "IND", ["DProperty_1", "ind_1", "INTEGER", "5"], ref=ref)
    armor.call("REASON", ref=ref)
    plain, inferred = tmp_path / "plain.owl", tmp_path / "inferred.owl"
    assert armor.call("SAVE", "", "", [str(plain)], ref=ref)["success"]
    assert armor.call("SAVE", "INFERENCE", "", [str(inferred)], ref=ref)["success"]
    c4 = f"<{TEST_IRI}#Class_4>"
    ind = f"<{TEST_IRI}#ind_1>"
    plain_triples = {str(q.triple) for q in parse(path=plain, format=RdfFormat.RDF_XML)}
    inferred_triples = {str(q.triple) for q in parse(path=inferred, format=RdfFormat.RDF_XML)}
    type_4 = f"{ind} <http://www.w3.org/1999/02/22-rdf-syntax-ns#type> {c4}"
    type_1 = f"{ind} <http://www.w3.org/1999/02/22-rdf-syntax-ns#type> <{TEST_IRI}#Class_1>"
    assert type_4 not in plain_triples and type_4 in inferred_triples and type_1 in inferred_triples
    # no side effect: the live reference still holds only what was asserted
    asserted = f"SELECT ?c WHERE {{ GRAPH ?g {{ {ind} a ?c }} FILTER(STRENDS(STR(?g), '{ref}')) }}"
    got = armor.call("QUERY", "SPARQL", "", [asserted], ref=ref, values="short")["queried_objects"][
        0
    ]
    assert "Class_4" not in got and "Class_2" in got
    # and the saved file loads back as a reference of its own
    again = armor.call(
        "LOAD", "FILE", "", [str(inferred), TEST_IRI, "false", "", "true"], ref=ref + "_again"
    )
    assert again["success"]
    classes = armor.call("QUERY", "IND", "", ["ind_1"], ref=ref + "_again", values="short")[
        "queried_objects"
    ]
    assert "Class_4" in classes


def test_save_empty_path_overwrites_the_loaded_file(armor: Armor, ref: str, tmp_path: Path) -> None:
    path = tmp_path / "onto.ttl"
    path.write_text(TURTLE)
    armor.call("LOAD", "FILE", "", [str(path), "http://ex.org/t", "false", "", "true"], ref=ref)
    armor.call("ADD", "IND", "CLASS", ["k2", "Kitchen"], ref=ref)
    assert armor.call("SAVE", "", "", [""], ref=ref)["success"]
    assert "k2" in path.read_text()
    parse(path=path, format=RdfFormat.TURTLE)  # still Turtle


def test_load_of_an_existing_name_does_not_reload(armor: Armor, ref: str, tmp_path: Path) -> None:
    path = tmp_path / "t.ttl"
    path.write_text(TURTLE)
    armor.call("LOAD", "FILE", "", [str(path), "http://ex.org/t", "false", "", "true"], ref=ref)
    armor.call("REMOVE", "IND", "", ["k1"], ref=ref)
    # the reasoner is buffered: it answers from the ontology as loaded until REASON, as in ARMOR
    assert armor.call("QUERY", "IND", "CLASS", ["Room"], ref=ref)["queried_objects"] == [
        "<http://ex.org/t#k1>"
    ]
    armor.call("REASON", "", "", [], ref=ref)
    armor.call("LOAD", "FILE", "", [str(path), "http://ex.org/t", "true", "", "true"], ref=ref)
    assert armor.call("QUERY", "IND", "CLASS", ["Room"], ref=ref)["queried_objects"] == []
    armor.call(
        "ADD", "IND", "CLASS", ["k3", "Room"], ref=ref
    )  # now buffered: the flag was re-applied
    assert armor.call("QUERY", "IND", "CLASS", ["Room"], ref=ref)["queried_objects"] == []


def test_malformed_files_answer_209(armor: Armor, ref: str, tmp_path: Path) -> None:
    for name, text in (
        ("bad.ttl", "@prefix : <x> . :a :b"),
        ("bad.owx", "<Ontology xmlns='http://www.w3.org/2002/07/owl#'><Frobnicate/></Ontology>"),
    ):
        path = tmp_path / name
        path.write_text(text)
        result = armor.call("LOAD", "FILE", "", [str(path), "http://ex.org/t"], ref=ref)
        assert (result["success"], result["exit_code"]) == (False, 209)
        assert name in result["error_description"]
    assert ref not in armor.call("GET", "ALL", "REFS", ref=ref)["queried_objects"]


def test_owlxml_reader_maps_protege_axioms() -> None:
    triples = {str(t) for t in owlxml_triples((DATA / "test.owx").read_bytes())}
    iri = TEST_IRI + "#"
    assert (
        f"<{iri}Class_2> <http://www.w3.org/2000/01/rdf-schema#subClassOf> <{iri}Class_1>"
        in triples
    )
    assert (
        f'<{iri}ind_0> <{iri}DProperty_1> "42"^^<http://www.w3.org/2001/XMLSchema#integer>'
        in triples
    )
    assert f'<{iri}Class_4> <http://www.w3.org/2000/01/rdf-schema#label> "class four"@en' in triples
    assert any("swrl#Imp" in t for t in triples) and any("swrlb#greaterThan" in t for t in triples)
    assert any("owl#annotatedSource" in t for t in triples)


def test_owlxml_reader_refuses_rdfxml_and_unknown_elements() -> None:
    with pytest.raises(OwlXmlError, match="expected OWL's <Ontology>"):
        owlxml_triples((DATA / "test.owl").read_bytes())
    with pytest.raises(OwlXmlError, match="Frobnicate"):
        owlxml_triples(b"<Ontology xmlns='http://www.w3.org/2002/07/owl#'><Frobnicate/></Ontology>")


def test_client_errors_and_fixed_bugs(armor: Armor, ref: str, tmp_path: Path) -> None:
    client = ArmorClient("c1", ref, base_url=armor.url)
    with pytest.raises(ArmorServiceInternalError) as missing:
        client.manipulation.add_ind_to_class("a", "B")
    assert missing.value.exit_code == 207 and str(missing.value).startswith(
        "ARMOR internal error 207: "
    )
    client.utils.load_ref_from_file("", "http://ex.org/c", mounted=True)
    assert client.utils.get_ref_client() == "c1"
    other = ArmorClient("c2", ref, base_url=armor.url)
    with pytest.raises(ArmorServiceInternalError) as busy:
        other.manipulation.add_ind_to_class("a", "B")
    assert busy.value.exit_code == 102
    client.utils.unmount_from_ref()
    client.manipulation.add_batch_dataprop_to_ind(
        "a", [["p", "INTEGER", "1"], ["q", "STRING", "x"]]
    )
    assert client.manipulation.remove_batch_dataprop_to_ind("a", [["p", "INTEGER", "1"]]) is True
    assert client.query.dataprop_b2_ind("p", "a") == []
    client.manipulation.add_dataprop_to_ind("q", "a", "STRING", "y")
    with pytest.raises(ArmorServiceInternalError) as many:
        client.manipulation.replace_one_dataprop_b2_ind("q", "a", "STRING", "z")
    assert many.value.exit_code == "206"
    client.manipulation.replace_one_objectprop_b2_ind("near", "a", "b")
    client.manipulation.replace_one_objectprop_b2_ind("near", "a", "c")
    assert client.query.objectprop_b2_ind("near", "a") == ["c"]
    assert client.query.objectprop_b2_ind("near", "a", with_URI=True) == ["<http://ex.org/c#c>"]
    client.utils.set_log_to_file(True, str(tmp_path / "log.txt"))
    client.utils.set_log_to_file(False)  # armor_py_api raised a TypeError here
    client.utils.set_log_to_terminal(False)
    client.utils.save(str(tmp_path / "out.owl"))
    assert (tmp_path / "out.owl").exists()
    assert ref in client.utils.get_all_refs()
    client.close()
    other.close()
    unreachable = ArmorClient("c", ref, base_url="http://127.0.0.1:9", timeout=1)
    with pytest.raises(ArmorServiceCallError):
        unreachable.query.check_ind_exists("a")
    unreachable.close()


def test_writes_need_the_token_when_one_is_set(tmp_path: Path) -> None:
    from tests.api.armor.conftest import start_live_server

    with start_live_server(tmp_path / "data", token="s3cret") as running:
        client = ArmorClient("c", "r", base_url=running.url)
        with pytest.raises(ArmorServiceCallError, match="401"):
            client.utils.get_all_refs()
        authorised = ArmorClient("c", "r", base_url=running.url, token="s3cret")
        authorised.utils.load_ref_from_file("", "http://ex.org/r")
        assert authorised.utils.get_all_refs() == ["r"]
        client.close()
        authorised.close()


def test_references_survive_a_restart(tmp_path: Path) -> None:
    from tests.api.armor.conftest import start_live_server

    for attempt in range(2):
        with start_live_server(tmp_path / "data") as running:
            client = ArmorClient("c", "kept", base_url=running.url)
            if attempt == 0:
                client.utils.load_ref_from_file("", "http://ex.org/kept", True, "PELLET", True)
                client.manipulation.add_dataprop_to_ind("stamp", "a", "LONG", "7")
                client.utils.apply_buffered_changes()
            else:
                assert client.utils.get_all_refs() == ["kept"]
                assert client.query.dataprop_b2_ind("stamp", "a") == ['"7"^^xsd:long']
                client.manipulation.add_ind_to_class("b", "C")  # still buffered after the restart
                assert client.query.ind_b2_class("C") == []
            client.close()
