"""The OWL export: one ontology, declared entities, blank-node class expressions, round trips."""

import datetime as dt
import shutil
from pathlib import Path

import pytest
import rdflib
import rdflib.compare
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from pyoxigraph import BlankNode, Literal, NamedNode, Triple
from rdflib.namespace import OWL, RDF, XSD

from kg import Store, ensure_ontology
from kg.export import export, export_triples
from kg.skolem import Deskolemiser
from kg.transaction import Transaction
from ontologies.vocab import (
    COMPLEXITY,
    CREATED,
    EPISODIC,
    EXPORT_ONTOLOGY_IRI,
    LEVEL,
    MEMORY,
    OWL_CLASS,
    OWL_EQUIVALENT_CLASS,
    OWL_INTERSECTION_OF,
    OWL_MIN_QUALIFIED_CARDINALITY,
    OWL_ON_CLASS,
    OWL_ON_PROPERTY,
    OWL_RESTRICTION,
    PINNED,
    PRIMITIVE_LEAF_TYPES,
    RDF_FIRST,
    RDF_NIL,
    RDF_REST,
    RDF_TYPE,
    RDFS_LABEL,
    RDFS_SUBCLASSOF,
    SCENE,
    SCORE,
    TBOX,
    XSD_DATETIME,
    engram,
)

SIGNATURE_PROPERTIES = [
    engram(f"{leaf}{relation}")
    for leaf in ("sphere", "cylinder", "cone", "plane")
    for relation in ("IsAboveOf", "IsBelowOf", "IsRightOf", "IsParallelWith")
]


def learn_class(
    tx: Transaction, name: str, signature: dict[tuple[NamedNode, NamedNode], int]
) -> NamedNode:
    """Write a scene class the way the scene memory does: C ≡ ⊓(≥n p.T), C ⊑ Scene."""
    cls = engram(name)
    tx.insert(cls, RDF_TYPE, OWL_CLASS, MEMORY)
    tx.insert(cls, RDFS_SUBCLASSOF, SCENE, MEMORY)
    restrictions = []
    for (prop, leaf), n in sorted(signature.items(), key=str):
        node = BlankNode()
        tx.insert(node, RDF_TYPE, OWL_RESTRICTION, MEMORY)
        tx.insert(node, OWL_ON_PROPERTY, prop, MEMORY)
        tx.insert(node, OWL_ON_CLASS, leaf, MEMORY)
        tx.insert(node, OWL_MIN_QUALIFIED_CARDINALITY, Literal(n), MEMORY)
        restrictions.append(node)
    head: NamedNode | BlankNode = RDF_NIL
    for node in reversed(restrictions):
        cell = BlankNode()
        tx.insert(cell, RDF_FIRST, node, MEMORY)
        tx.insert(cell, RDF_REST, head, MEMORY)
        head = cell
    definition = BlankNode()
    tx.insert(definition, RDF_TYPE, OWL_CLASS, MEMORY)
    tx.insert(definition, OWL_INTERSECTION_OF, head, MEMORY)
    tx.insert(cls, OWL_EQUIVALENT_CLASS, definition, MEMORY)
    tx.insert(cls, COMPLEXITY, Literal(sum(signature.values())), MEMORY)
    return cls


@pytest.fixture
def memory_with_two_classes(store_with_ontology: Store) -> Store:
    sphere, plane = engram("Sphere"), engram("Plane")
    with store_with_ontology.transaction() as tx:
        learn_class(tx, "Scene-1", {(engram("sphereIsAboveOf"), plane): 1})
        learn_class(
            tx,
            "Scene-2",
            {(engram("sphereIsAboveOf"), plane): 2, (engram("planeIsBelowOf"), sphere): 1},
        )
        scene = engram("scene-42")
        tx.insert(scene, RDF_TYPE, SCENE, EPISODIC)
        tx.insert(scene, RDFS_LABEL, Literal("what the robot saw"), EPISODIC)
    return store_with_ontology


def parsed(data: bytes, fmt: str) -> rdflib.Graph:
    graph = rdflib.Graph()
    graph.parse(data=data, format="xml" if fmt == "rdfxml" else "turtle")
    return graph


@pytest.mark.parametrize("fmt", ["rdfxml", "turtle"])
def test_export_is_one_ontology_with_blank_node_restrictions(
    memory_with_two_classes: Store, fmt: str
) -> None:
    graph = parsed(export(memory_with_two_classes, format=fmt), fmt)
    assert list(graph.subjects(RDF.type, OWL.Ontology)) == [
        rdflib.URIRef(EXPORT_ONTOLOGY_IRI.value)
    ]
    restrictions = list(graph.subjects(RDF.type, OWL.Restriction))
    assert len(restrictions) == 3
    assert all(isinstance(node, rdflib.BNode) for node in restrictions)
    assert not any(".well-known/genid" in str(term) for triple in graph for term in triple)
    cardinalities = list(graph.objects(None, OWL.minQualifiedCardinality))
    assert {c.datatype for c in cardinalities} == {XSD.nonNegativeInteger}


def test_episodic_individuals_only_on_request(memory_with_two_classes: Store) -> None:
    scene = rdflib.URIRef(engram("scene-42").value)
    default = parsed(export(memory_with_two_classes, format="turtle"), "turtle")
    with_episodes = parsed(
        export(memory_with_two_classes, ["tbox", "memory", "episodic"], "turtle"), "turtle"
    )
    assert (scene, None, None) not in default
    assert (scene, RDF.type, OWL.NamedIndividual) in with_episodes


def test_missing_declarations_are_added_by_use() -> None:
    store = Store()
    with store.transaction() as tx:
        tx.insert(engram("x"), RDF_TYPE, engram("Thing"), MEMORY)
        tx.insert(engram("x"), engram("weight"), Literal(2.5), MEMORY)
        tx.insert(engram("x"), engram("near"), engram("y"), MEMORY)
        tx.insert(engram("x"), engram("note"), Literal("n"), MEMORY)
        tx.insert(engram("y"), engram("note"), engram("x"), MEMORY)
    declared = {
        (t.subject.value.rsplit("#")[-1], t.object.value.rsplit("#")[-1])
        for t in export_triples(store, ["memory"])
        if t.predicate == RDF_TYPE and t.subject != EXPORT_ONTOLOGY_IRI
    }
    assert declared >= {
        ("Thing", "Class"),
        ("x", "NamedIndividual"),
        ("weight", "DatatypeProperty"),
        ("near", "ObjectProperty"),
        ("note", "AnnotationProperty"),
    }


def test_rdfxml_export_refuses_characters_xml_cannot_carry(empty_store: Store) -> None:
    with empty_store.transaction() as tx:
        tx.insert(engram("x"), RDFS_LABEL, Literal("bell\x07"), MEMORY)
    with pytest.raises(ValueError, match=r"U\+0007, which XML 1\.0 cannot carry"):
        export(empty_store, ["memory"], "rdfxml")
    assert b"bell" in export(empty_store, ["memory"], "turtle")


@pytest.mark.parametrize("label", ["\r", "a\r\nb", "tab\there"])
def test_rdfxml_export_keeps_carriage_returns_and_tabs(empty_store: Store, label: str) -> None:
    with empty_store.transaction() as tx:
        tx.insert(engram("x"), RDFS_LABEL, Literal(label), MEMORY)
    graph = parsed(export(empty_store, ["memory"], "rdfxml"), "rdfxml")
    assert rdflib.Literal(label) in set(graph.objects(rdflib.URIRef(engram("x").value), None))


def test_export_without_the_tbox_declares_entities_as_the_tbox_does(
    memory_with_two_classes: Store,
) -> None:
    with memory_with_two_classes.transaction() as tx:
        tx.insert(engram("Scene-1"), SCORE, Literal(0.5), MEMORY)
    kinds = {
        t.subject: t.object
        for t in export_triples(memory_with_two_classes, ["memory"])
        if t.predicate == RDF_TYPE
    }
    assert kinds[SCORE].value.endswith("#AnnotationProperty")
    assert kinds[COMPLEXITY].value.endswith("#AnnotationProperty")
    assert kinds[engram("sphereIsAboveOf")].value.endswith("#ObjectProperty")


@pytest.mark.parametrize(
    ("graphs", "fmt", "message"),
    [
        (["tbox", "nope"], "turtle", "graphs: got"),
        ([], "turtle", "non-empty"),
        (["tbox"], "owl/xml", "format: got 'owl/xml'"),
    ],
)
def test_bad_export_arguments_name_what_is_accepted(
    store_with_ontology: Store, graphs: list[str], fmt: str, message: str
) -> None:
    with pytest.raises(ValueError, match=message):
        export(store_with_ontology, graphs, fmt)


def test_export_loads_in_owlready2(memory_with_two_classes: Store, tmp_path: Path) -> None:
    owlready2 = pytest.importorskip("owlready2")
    path = tmp_path / "engram.owl"
    path.write_bytes(export(memory_with_two_classes, ["tbox", "memory", "episodic"], "rdfxml"))
    world = owlready2.World()
    onto = world.get_ontology(path.as_uri()).load()
    names = {cls.name for cls in onto.classes()}
    assert {"Sphere", "Cone", "Scene", "Scene-1", "Scene-2"} <= names
    scene_2 = onto.search_one(iri="*Scene-2")
    assert len(scene_2.equivalent_to) == 1
    assert {p.name for p in onto.data_properties()} >= {"centreX", "learnThreshold"}
    assert {p.name for p in onto.annotation_properties()} >= {"rawScore", "pinned"}


@pytest.mark.skipif(
    shutil.which("java") is None, reason="HermiT needs Java; scripts/test installs it"
)
def test_hermit_classifies_the_export(memory_with_two_classes: Store, tmp_path: Path) -> None:
    """HermiT, the reasoner Protégé ships, finds the memory consistent and Scene-2 ⊑ Scene-1."""
    owlready2 = pytest.importorskip("owlready2")
    path = tmp_path / "engram.owl"
    path.write_bytes(export(memory_with_two_classes, ["tbox", "memory"], "rdfxml"))
    world = owlready2.World()
    onto = world.get_ontology(path.as_uri()).load()
    with onto:
        owlready2.sync_reasoner_hermit(world, infer_property_values=False, debug=0)
    scene_1, scene_2 = onto.search_one(iri="*Scene-1"), onto.search_one(iri="*Scene-2")
    assert scene_1 in scene_2.ancestors()
    assert owlready2.Nothing not in scene_2.equivalent_to


@st.composite
def memories(draw: st.DrawFn) -> list[tuple[str, dict[tuple[NamedNode, NamedNode], int], dict]]:
    count = draw(st.integers(min_value=1, max_value=4))
    classes = []
    for k in range(count):
        signature = draw(
            st.dictionaries(
                st.tuples(
                    st.sampled_from(SIGNATURE_PROPERTIES), st.sampled_from(PRIMITIVE_LEAF_TYPES)
                ),
                st.integers(min_value=1, max_value=5),
                min_size=1,
                max_size=4,
            )
        )
        notes = {
            "score": draw(st.floats(min_value=0, max_value=1, allow_nan=False)),
            "level": draw(st.sampled_from(["HIGH", "LOW", "WEAK"])),
            "pinned": draw(st.booleans()),
            "label": draw(
                st.text(
                    st.characters(exclude_categories=["Cs", "Cc"]) | st.sampled_from("\t\n\r"),
                    max_size=20,
                )
            ),
            "created": draw(
                st.datetimes(
                    min_value=dt.datetime(2000, 1, 1),
                    max_value=dt.datetime(2100, 1, 1),
                    timezones=st.just(dt.UTC),
                )
            ).replace(microsecond=0),
        }
        classes.append((f"Scene-{k}", signature, notes))
    return classes


def to_rdflib(term: object) -> rdflib.term.Node:
    if isinstance(term, NamedNode):
        return rdflib.URIRef(term.value)
    if isinstance(term, BlankNode):
        return rdflib.BNode(term.value)
    assert isinstance(term, Literal)
    if term.language:
        return rdflib.Literal(term.value, lang=term.language)
    if term.datatype.value == str(XSD.string):  # RDF 1.1: a simple literal is an xsd:string
        return rdflib.Literal(term.value)
    return rdflib.Literal(term.value, datatype=rdflib.URIRef(term.datatype.value))


def comparable(graph: rdflib.Graph) -> rdflib.Graph:
    """Literals by value, so that 1.0E0 and 1.0 compare equal; the structure stays exact."""
    out = rdflib.Graph()
    for s, p, o in graph:
        if isinstance(o, rdflib.Literal) and o.datatype is not None:
            o = rdflib.Literal(o.toPython(), datatype=o.datatype)
        out.add((s, p, o))
    return out


@settings(
    max_examples=20,
    deadline=None,
    suppress_health_check=[HealthCheck.function_scoped_fixture],
)
@given(memory=memories(), fmt=st.sampled_from(["rdfxml", "turtle"]))
def test_parse_of_export_gives_back_the_stored_triples(memory: list, fmt: str) -> None:
    store = Store()
    ensure_ontology(store)
    with store.transaction() as tx:
        for name, signature, notes in memory:
            cls = learn_class(tx, name, signature)
            tx.insert(cls, SCORE, Literal(notes["score"]), MEMORY)
            tx.insert(cls, LEVEL, Literal(notes["level"]), MEMORY)
            tx.insert(cls, PINNED, Literal(notes["pinned"]), MEMORY)
            tx.insert(cls, RDFS_LABEL, Literal(notes["label"], language="en"), MEMORY)
            tx.insert(
                cls, CREATED, Literal(notes["created"].isoformat(), datatype=XSD_DATETIME), MEMORY
            )
    back = parsed(export(store, ["tbox", "memory"], fmt), fmt)

    deskolemise = Deskolemiser()
    expected = rdflib.Graph()
    for graph in (TBOX, MEMORY):
        for quad in store.quads(graph=graph):
            triple: Triple = deskolemise.triple(quad.triple)
            obj = to_rdflib(triple.object)
            if triple.predicate == OWL_MIN_QUALIFIED_CARDINALITY:
                obj = rdflib.Literal(str(obj), datatype=XSD.nonNegativeInteger)
            expected.add((to_rdflib(triple.subject), to_rdflib(triple.predicate), obj))
    tbox_header = rdflib.URIRef("https://w3id.org/engram/ontology")
    expected.remove((tbox_header, None, None))
    export_header = rdflib.URIRef(EXPORT_ONTOLOGY_IRI.value)
    back.remove((export_header, None, None))
    back.remove(
        (rdflib.URIRef("http://purl.org/dc/terms/created"), RDF.type, OWL.AnnotationProperty)
    )

    assert rdflib.compare.isomorphic(comparable(back), comparable(expected))
