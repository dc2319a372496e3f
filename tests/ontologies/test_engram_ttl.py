"""The Engram T-Box: complete, documented and OWL 2 DL."""

from collections import defaultdict

import pytest
import rdflib
from rdflib.namespace import OWL, RDF, RDFS, XSD

from ontologies import ENGRAM_TTL

ENGRAM = rdflib.Namespace("https://w3id.org/engram/ontology#")
ENTITY_KINDS = {
    OWL.Class,
    OWL.ObjectProperty,
    OWL.DatatypeProperty,
    OWL.AnnotationProperty,
    OWL.NamedIndividual,
}
LEAVES = [ENGRAM.Sphere, ENGRAM.Cylinder, ENGRAM.Cone, ENGRAM.Plane]


@pytest.fixture(scope="module")
def tbox() -> rdflib.Graph:
    graph = rdflib.Graph()
    graph.parse(ENGRAM_TTL, format="turtle")
    return graph


def engram_entities(tbox: rdflib.Graph) -> dict[rdflib.URIRef, set[rdflib.URIRef]]:
    kinds: dict[rdflib.URIRef, set[rdflib.URIRef]] = defaultdict(set)
    for subject, kind in tbox.subject_objects(RDF.type):
        if kind in ENTITY_KINDS and isinstance(subject, rdflib.URIRef):
            kinds[subject].add(kind)
    return kinds


def test_has_one_ontology_with_a_version_iri(tbox: rdflib.Graph) -> None:
    ontologies = list(tbox.subjects(RDF.type, OWL.Ontology))
    assert ontologies == [rdflib.URIRef("https://w3id.org/engram/ontology")]
    assert len(list(tbox.objects(ontologies[0], OWL.versionIRI))) == 1


def test_every_entity_has_exactly_one_kind(tbox: rdflib.Graph) -> None:
    """No punning, and no property declared as two kinds (OWL 2 DL)."""
    punned = {entity: kinds for entity, kinds in engram_entities(tbox).items() if len(kinds) != 1}
    assert punned == {}


def test_every_engram_term_is_declared_labelled_and_commented(tbox: rdflib.Graph) -> None:
    used = {
        term
        for triple in tbox
        for term in triple
        if isinstance(term, rdflib.URIRef) and term.startswith(str(ENGRAM))
    }
    declared = engram_entities(tbox)
    assert used - declared.keys() == set()
    missing = {
        term: [p for p in (RDFS.label, RDFS.comment) if (term, p, None) not in tbox]
        for term in used
    }
    assert {term: gaps for term, gaps in missing.items() if gaps} == {}


def test_primitive_hierarchy(tbox: rdflib.Graph) -> None:
    assert (ENGRAM.Sphere, RDFS.subClassOf, ENGRAM.GeometricPrimitive) in tbox
    assert (ENGRAM.Orientable, RDFS.subClassOf, ENGRAM.GeometricPrimitive) in tbox
    for leaf in (ENGRAM.Cylinder, ENGRAM.Cone, ENGRAM.Plane):
        assert (leaf, RDFS.subClassOf, ENGRAM.Orientable) in tbox


def test_leaf_primitives_are_pairwise_disjoint(tbox: rdflib.Graph) -> None:
    member_lists = [
        set(rdflib.collection.Collection(tbox, members))
        for axiom in tbox.subjects(RDF.type, OWL.AllDisjointClasses)
        for members in tbox.objects(axiom, OWL.members)
    ]
    assert set(LEAVES) in member_lists


@pytest.mark.parametrize(
    ("relation", "inverse"),
    [("isRightOf", "isLeftOf"), ("isBehindOf", "isInFrontOf"), ("isAboveOf", "isBelowOf")],
)
def test_ordered_relations_are_inverse_pairs_and_transitive(
    tbox: rdflib.Graph, relation: str, inverse: str
) -> None:
    assert (ENGRAM[relation], OWL.inverseOf, ENGRAM[inverse]) in tbox
    for name in (relation, inverse):
        assert (ENGRAM[name], RDF.type, OWL.TransitiveProperty) in tbox
        assert (ENGRAM[name], RDF.type, OWL.SymmetricProperty) not in tbox


@pytest.mark.parametrize(
    "relation",
    [
        "isParallelWith",
        "isPerpendicularWith",
        "isCoaxialWith",
        "isAlongXWith",
        "isAlongYWith",
        "isAlongZWith",
    ],
)
def test_approximate_relations_are_symmetric_not_transitive(
    tbox: rdflib.Graph, relation: str
) -> None:
    assert (ENGRAM[relation], RDF.type, OWL.SymmetricProperty) in tbox
    assert (ENGRAM[relation], RDF.type, OWL.TransitiveProperty) not in tbox


@pytest.mark.parametrize(
    "name",
    [
        "complexity",
        "storeCount",
        "retrieveCount",
        "rawScore",
        "sleepLevel",
        "sleepLevels",
        "scoreTerms",
        "scoreTermComplexity",
        "scoreTermStore",
        "scoreTermRetrieve",
        "created",
        "lastAccessed",
        "consecutiveWeakCount",
        "pinned",
    ],
)
def test_memory_item_values_are_annotation_properties(tbox: rdflib.Graph, name: str) -> None:
    """Values on class IRIs must be annotations, or the memory would be OWL Full."""
    assert engram_entities(tbox)[ENGRAM[name]] == {OWL.AnnotationProperty}


def test_there_is_one_signature_property_per_leaf_type_and_relation(tbox: rdflib.Graph) -> None:
    relations = {
        s
        for s, o in tbox.subject_objects(RDF.type)
        if o == OWL.ObjectProperty and (s, RDFS.domain, ENGRAM.GeometricPrimitive) in tbox
    } | {
        s
        for s in tbox.subjects(RDFS.domain, ENGRAM.Orientable)
        if (s, RDF.type, OWL.ObjectProperty) in tbox
    }
    pairs = {
        (tbox.value(p, ENGRAM.signatureSubjectType), tbox.value(p, ENGRAM.signatureRelation))
        for p in tbox.subjects(ENGRAM.signatureRelation, None)
    }
    assert len(relations) == 12
    assert pairs == {(leaf, relation) for leaf in LEAVES for relation in relations}


def test_default_policy_sets_every_policy_property_once_with_its_datatype(
    tbox: rdflib.Graph,
) -> None:
    policy_properties = set(tbox.subjects(RDFS.domain, ENGRAM.MemoryPolicy))
    assert len(policy_properties) >= 20
    for prop in policy_properties:
        values = list(tbox.objects(ENGRAM.defaultPolicy, prop))
        assert len(values) == 1, prop
        assert values[0].datatype == tbox.value(prop, RDFS.range), prop


@pytest.mark.parametrize(
    ("name", "value"),
    [
        ("alignedThresholdX", 0.05),
        ("parallelThreshold", 0.7),
        ("perpendicularThreshold", 0.7),
        ("coaxialThreshold", 0.05),
        ("learnThreshold", 0.8),
        ("complexityWeight", 0.2),
        ("childrenWeight", 0.2),
        ("storeWeight", 0.3),
        ("retrieveWeight", 0.3),
        ("decayWeight", 0.1),
        ("decayTimeConstantSeconds", 3600.0),
        ("highLevelThreshold", 0.6),
        ("weakLevelThreshold", 0.2),
        ("weakPassesToForget", 3),
    ],
)
def test_default_policy_holds_design_values(tbox: rdflib.Graph, name: str, value: float) -> None:
    literal = tbox.value(ENGRAM.defaultPolicy, ENGRAM[name])
    assert literal is not None
    assert literal.toPython() == value
    assert literal.datatype in (XSD.double, XSD.integer)
