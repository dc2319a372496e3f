"""ARMOR's own client example: ``Class_4 ≡ ∃OProperty_1.Class_3 ⊓ ∃DProperty_1.xsd:integer``.

armor_py_api's ``client_test.py`` loads ``test/test.owl``, adds ``ind_1`` with an object
property to a ``Class_3`` individual and an integer data property, and expects Pellet to put
``ind_1`` in ``Class_4``; then it replaces the data value 1 with 3.
"""

from pyoxigraph import Literal, NamedNode, RdfFormat

from ontologies.vocab import RDF_TYPE
from reasoners.owl_rl import is_consistent, materialise

from .conftest import ASSERTED, INFERRED, Loader

NS = "http://www.emarolab.it/armor_test#"
XSD = "http://www.w3.org/2001/XMLSchema#"

# As Protégé 5 writes it (RDF/XML, blank-node class expressions, declarations).
TEST_OWL = f"""<?xml version="1.0"?>
<rdf:RDF xmlns="{NS}" xml:base="{NS[:-1]}"
     xmlns:owl="http://www.w3.org/2002/07/owl#"
     xmlns:rdf="http://www.w3.org/1999/02/22-rdf-syntax-ns#"
     xmlns:xsd="{XSD}"
     xmlns:rdfs="http://www.w3.org/2000/01/rdf-schema#">
    <owl:Ontology rdf:about="{NS[:-1]}"/>
    <owl:ObjectProperty rdf:about="{NS}OProperty_1"/>
    <owl:DatatypeProperty rdf:about="{NS}DProperty_1"/>
    <owl:Class rdf:about="{NS}Class_1"/>
    <owl:Class rdf:about="{NS}Class_2"><rdfs:subClassOf rdf:resource="{NS}Class_1"/></owl:Class>
    <owl:Class rdf:about="{NS}Class_3"/>
    <owl:Class rdf:about="{NS}Class_4">
        <owl:equivalentClass>
            <owl:Class>
                <owl:intersectionOf rdf:parseType="Collection">
                    <owl:Restriction>
                        <owl:onProperty rdf:resource="{NS}OProperty_1"/>
                        <owl:someValuesFrom rdf:resource="{NS}Class_3"/>
                    </owl:Restriction>
                    <owl:Restriction>
                        <owl:onProperty rdf:resource="{NS}DProperty_1"/>
                        <owl:someValuesFrom rdf:resource="{XSD}integer"/>
                    </owl:Restriction>
                </owl:intersectionOf>
            </owl:Class>
        </owl:equivalentClass>
    </owl:Class>
    <owl:NamedIndividual rdf:about="{NS}ind_2"><rdf:type rdf:resource="{NS}Class_3"/>
    </owl:NamedIndividual>
</rdf:RDF>
"""

IND_1, CLASS_4 = NamedNode(NS + "ind_1"), NamedNode(NS + "Class_4")
OPROPERTY_1, DPROPERTY_1 = NamedNode(NS + "OProperty_1"), NamedNode(NS + "DProperty_1")


def _types(store, individual: NamedNode) -> set[NamedNode]:  # type: ignore[no-untyped-def]
    return {q.object for q in store.quads(individual, RDF_TYPE, None, INFERRED)}  # type: ignore[misc]


def test_individual_with_object_and_integer_property_is_inferred_into_class_4(
    load: Loader,
) -> None:
    store = load(TEST_OWL, RdfFormat.RDF_XML)
    integer = NamedNode(XSD + "integer")
    with store.transaction() as tx:  # what ADD IND CLASS / ADD OBJECTPROP / ADD DATAPROP write
        tx.insert(IND_1, RDF_TYPE, NamedNode(NS + "Class_2"), ASSERTED)
        tx.insert(IND_1, OPROPERTY_1, NamedNode(NS + "ind_2"), ASSERTED)
        tx.insert(IND_1, DPROPERTY_1, Literal("1", datatype=integer), ASSERTED)
    report = materialise(store, asserted=ASSERTED, inferred=INFERRED, reasoner="PELLET")
    assert report.consistent
    assert {CLASS_4, NamedNode(NS + "Class_1")} <= _types(store, IND_1)
    assert CLASS_4 not in _types(store, NamedNode(NS + "ind_2"))

    # client_test.py then replaces DProperty_1 1 -> 3: still an integer, still Class_4
    with store.transaction() as tx:
        tx.delete(IND_1, DPROPERTY_1, Literal("1", datatype=integer), ASSERTED)
        tx.insert(IND_1, DPROPERTY_1, Literal("3", datatype=integer), ASSERTED)
    report = materialise(store, asserted=ASSERTED, inferred=INFERRED, reasoner="pellet")
    assert CLASS_4 in _types(store, IND_1)
    assert is_consistent(store, asserted=ASSERTED, inferred=INFERRED).consistent


def test_a_string_value_or_a_missing_link_does_not_make_class_4(load: Loader) -> None:
    store = load(TEST_OWL, RdfFormat.RDF_XML)
    with store.transaction() as tx:
        tx.insert(IND_1, OPROPERTY_1, NamedNode(NS + "ind_2"), ASSERTED)
        tx.insert(IND_1, DPROPERTY_1, Literal("one"), ASSERTED)
        tx.insert(
            NamedNode(NS + "ind_3"),
            DPROPERTY_1,
            Literal("2", datatype=NamedNode(XSD + "integer")),
            ASSERTED,
        )
    materialise(store, asserted=ASSERTED, inferred=INFERRED, reasoner="HERMIT")
    assert CLASS_4 not in _types(store, IND_1)
    assert CLASS_4 not in _types(store, NamedNode(NS + "ind_3"))
    # the string is fixed into an integer: the next REASON classifies ind_1
    with store.transaction() as tx:
        tx.insert(IND_1, DPROPERTY_1, Literal("5", datatype=NamedNode(XSD + "integer")), ASSERTED)
    report = materialise(store, asserted=ASSERTED, inferred=INFERRED, reasoner="HERMIT")
    assert report.incremental
    assert CLASS_4 in _types(store, IND_1)
