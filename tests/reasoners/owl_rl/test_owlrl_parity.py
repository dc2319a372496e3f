"""REASON infers exactly what owlrl infers on the same input, for the rules both implement."""

import owlrl
import pytest
import rdflib
from owlrl.AxiomaticTriples import OWLRL_Datatypes_Disjointness
from pyoxigraph import RdfFormat, parse

from reasoners.owl_rl import closure, materialise
from reasoners.owl_rl.synthetic import scene_ontology

from .conftest import ASSERTED, INFERRED, Loader, graph_triples, owlrl_inferences

SAME_AS = "<http://www.w3.org/2002/07/owl#sameAs>"
PREFIXES = """
@prefix : <http://example.org/> .
@prefix owl: <http://www.w3.org/2002/07/owl#> .
@prefix rdf: <http://www.w3.org/1999/02/22-rdf-syntax-ns#> .
@prefix rdfs: <http://www.w3.org/2000/01/rdf-schema#> .
@prefix xsd: <http://www.w3.org/2001/XMLSchema#> .
"""

# One small ontology per rule family, each with the instance data that makes the rule fire.
CASES = {
    "subclass, equivalence, domain and range": """
        :Cube rdfs:subClassOf :Box . :Box rdfs:subClassOf :Primitive .
        :Primitive owl:equivalentClass :Shape . :Cube a owl:Class . :Box a owl:Class .
        :onTable a owl:ObjectProperty ; rdfs:domain :Cube ; rdfs:range :Table .
        :c1 :onTable :t1 . :c2 a :Cube .""",
    "property hierarchy, inverse, symmetric, transitive": """
        :onTopOf rdfs:subPropertyOf :above . :above a owl:TransitiveProperty .
        :below owl:inverseOf :above . :near a owl:SymmetricProperty .
        :touches owl:equivalentProperty :contacts . :above rdfs:domain :Thing2 .
        :a :onTopOf :b . :b :above :c . :c :above :d . :a :near :b . :a :touches :c .""",
    "property chain": """
        :hasUncle owl:propertyChainAxiom ( :hasParent :hasBrother ) .
        :hasGrandparent owl:propertyChainAxiom ( :hasParent :hasParent ) .
        :ann :hasParent :bob . :bob :hasBrother :carl . :bob :hasParent :dora .""",
    "functional, inverse functional and equality": """
        :hasSerial a owl:InverseFunctionalProperty . :hasBody a owl:FunctionalProperty .
        :r1 :hasSerial :s . :r2 :hasSerial :s . :r1 :hasBody :b1 . :r1 :hasBody :b2 .
        :r2 :colour :red . :b1 a :Body . :x owl:sameAs :y . :y owl:sameAs :z . :z :p :w .""",
    "intersection, union, some/all/has-value restrictions": """
        :Mug owl:equivalentClass [ owl:intersectionOf ( :Container :Graspable ) ] .
        :Round owl:unionOf ( :Sphere :Cylinder ) .
        :Stacked owl:equivalentClass [ a owl:Restriction ; owl:onProperty :above ;
                                       owl:someValuesFrom :Primitive ] .
        :AnyOn owl:equivalentClass [ a owl:Restriction ; owl:onProperty :on ;
                                     owl:someValuesFrom owl:Thing ] .
        :Red owl:equivalentClass [ a owl:Restriction ; owl:onProperty :colour ;
                                   owl:hasValue :red ] .
        :Tray rdfs:subClassOf [ a owl:Restriction ; owl:onProperty :holds ;
                                owl:allValuesFrom :Cup ] .
        :Scored owl:equivalentClass [ a owl:Restriction ; owl:onProperty :score ;
                                      owl:someValuesFrom xsd:decimal ] .
        :m a :Container , :Graspable . :n a :Mug . :s a :Sphere . :a :above :p . :p a :Primitive .
        :o :on :q . :r :colour :red . :red2 a :Red . :tr a :Tray ; :holds :h .
        :k :score "3"^^xsd:integer . :k2 :score "0.5"^^xsd:double .""",
    "max cardinality one and one-of": """
        :Single owl:equivalentClass [ a owl:Restriction ; owl:onProperty :partner ;
                                      owl:maxCardinality "1"^^xsd:nonNegativeInteger ] .
        :OneCup rdfs:subClassOf [ a owl:Restriction ; owl:onProperty :has ;
            owl:maxQualifiedCardinality "1"^^xsd:nonNegativeInteger ; owl:onClass :Cup ] .
        :Colour owl:oneOf ( :red :green ) .
        :s1 a :Single ; :partner :p1 , :p2 . :o1 a :OneCup ; :has :c1 , :c2 , :plate .
        :c1 a :Cup . :c2 a :Cup .""",
    "schema rules on restrictions": """
        :r1 a owl:Restriction ; owl:onProperty :p ; owl:someValuesFrom :A .
        :r2 a owl:Restriction ; owl:onProperty :p ; owl:someValuesFrom :B .
        :A rdfs:subClassOf :B . :A a owl:Class . :B a owl:Class .
        :r3 a owl:Restriction ; owl:onProperty :q ; owl:allValuesFrom :A .
        :r4 a owl:Restriction ; owl:onProperty :q ; owl:allValuesFrom :B .
        :h1 a owl:Restriction ; owl:onProperty :sub ; owl:hasValue :v .
        :h2 a owl:Restriction ; owl:onProperty :super ; owl:hasValue :v .
        :sub rdfs:subPropertyOf :super . :sub a owl:ObjectProperty .
        :super rdfs:domain :D . :D rdfs:subClassOf :E . :x :sub :y .""",
}


@pytest.mark.parametrize("name", sorted(CASES))
def test_inferred_triples_equal_owlrl(load: Loader, name: str) -> None:
    store = load(PREFIXES + CASES[name])
    report = materialise(store, asserted=ASSERTED, inferred=INFERRED)
    expected = owlrl_inferences(store)
    assert graph_triples(store) == expected
    assert report.inferred_total == len(expected)
    assert not graph_triples(store) & graph_triples(store, ASSERTED)


def test_scene_ontology_equals_owlrl(load: Loader) -> None:
    store = load("\n".join(scene_ontology(1_500, seed=3)).encode(), RdfFormat.N_TRIPLES)
    materialise(store, asserted=ASSERTED, inferred=INFERRED)
    inferred = graph_triples(store)
    assert inferred == owlrl_inferences(store)
    # the defined classes are populated, including the data-range one (∃score.xsd:double)
    for defined in ("StackedObject", "ScoredObject", "GroundObject", "SceneWithContainer"):
        assert any(t.endswith(f"<http://example.org/scene#{defined}>") for t in inferred)


LITERALS = """
    :v rdfs:subPropertyOf :w . :a :v "5"^^xsd:byte , "7"^^xsd:long .
    :Counted owl:equivalentClass [ a owl:Restriction ; owl:onProperty :w ;
                                   owl:someValuesFrom xsd:byte ] ."""


@pytest.mark.parametrize("name", [*sorted(CASES), "literals of integer subtypes"])
def test_in_memory_closure_equals_owlrl_on_the_parsed_document(name: str) -> None:
    """The same Turtle to both reasoners, each parsing it (never through the store): the
    triples they add without a blank node or a literal subject are the same."""
    document = PREFIXES + CASES.get(name, LITERALS)
    premise = {
        (str(q.subject), str(q.predicate), str(q.object))
        for q in parse(document, format=RdfFormat.TURTLE)
    }
    facts, _ = closure(premise)
    graph = rdflib.Graph().parse(data=document, format="turtle")
    before = set(graph)
    owlrl.DeductiveClosure(owlrl.OWLRL_Semantics).expand(graph)
    added = {
        (s.n3(), p.n3(), o.n3())
        for s, p, o in set(graph) - before
        if (s, p, o) not in OWLRL_Datatypes_Disjointness
        and not str(p).startswith("http://www.daml.org/2002/03/agents/agent-ont#")
    }
    assert _comparable(facts - premise) == _comparable(added - premise)


def _comparable(triples: set[tuple[str, str, str]]) -> set[tuple[str, str, str]]:
    """Without blank nodes (named differently by each parser), literal subjects and eq-ref."""
    return {
        (s, p, o)
        for s, p, o in triples
        if s[0] not in '_"' and not o.startswith("_:") and not (p == SAME_AS and s == o)
    }
