"""The datatype rules (dt-type1, dt-type2, dt-eq, dt-diff, dt-not-type) over literals that keep
their datatype through the store."""

import pytest

from reasoners.owl_rl import is_consistent, materialise

from .conftest import ASSERTED, INFERRED, Loader, graph_triples
from .test_owlrl_parity import PREFIXES

EX = "http://example.org/"
XSD = "http://www.w3.org/2001/XMLSchema#"
TYPE = "<http://www.w3.org/1999/02/22-rdf-syntax-ns#type>"


def _reasoned(load: Loader, turtle: str) -> set[str]:
    store = load(PREFIXES + turtle)
    materialise(store, asserted=ASSERTED, inferred=INFERRED)
    return graph_triples(store)


def test_a_subtyped_literal_reaches_the_closure_with_its_datatype(load: Loader) -> None:
    inferred = _reasoned(load, ':v rdfs:subPropertyOf :w . :a :v "5"^^xsd:byte .')
    assert f'<{EX}a> <{EX}w> "5"^^<{XSD}byte>' in inferred


@pytest.mark.parametrize(
    ("datatype", "value"),
    [
        ("xsd:nonNegativeInteger", '"5"^^xsd:nonNegativeInteger'),
        ("xsd:nonNegativeInteger", "5"),  # value spaces, not lexical datatypes
        ("xsd:byte", '"5"^^xsd:long'),
        ("xsd:string", '"a plain string"'),
        ("rdf:PlainLiteral", '"chat"@fr'),
        ("rdfs:Literal", '"2026-01-01T00:00:00Z"^^xsd:dateTimeStamp'),
        ("xsd:dateTime", '"2026-01-01T00:00:00Z"^^xsd:dateTimeStamp'),
        ("xsd:decimal", "5"),
    ],
)
def test_some_values_from_a_datatype_holds_for_the_literals_in_its_value_space(
    load: Loader, datatype: str, value: str
) -> None:
    inferred = _reasoned(
        load,
        f":C owl:equivalentClass [ a owl:Restriction ; owl:onProperty :v ; "
        f"owl:someValuesFrom {datatype} ] . :a :v {value} .",
    )
    assert f"<{EX}a> {TYPE} <{EX}C>" in inferred


@pytest.mark.parametrize(
    ("datatype", "value"),
    [
        ("xsd:byte", "300"),
        ("xsd:nonNegativeInteger", "-1"),
        ("xsd:string", "5"),
        ("xsd:byte", '"5"^^xsd:double'),
    ],
)
def test_some_values_from_a_datatype_does_not_hold_outside_its_value_space(
    load: Loader, datatype: str, value: str
) -> None:
    inferred = _reasoned(
        load,
        f":C owl:equivalentClass [ a owl:Restriction ; owl:onProperty :v ; "
        f"owl:someValuesFrom {datatype} ] . :a :v {value} .",
    )
    assert f"<{EX}a> {TYPE} <{EX}C>" not in inferred


def test_every_datatype_of_the_map_is_a_datatype(load: Loader) -> None:  # dt-type1
    inferred = _reasoned(load, ":a :v 1 .")
    datatype = "<http://www.w3.org/2000/01/rdf-schema#Datatype>"
    assert f"<{XSD}byte> {TYPE} {datatype}" in inferred
    assert f"<{XSD}dateTimeStamp> {TYPE} {datatype}" in inferred
    assert "<http://www.w3.org/2002/07/owl#real>" not in str(inferred)  # outside OWL 2 RL


@pytest.mark.parametrize(
    ("turtle", "rule"),
    [
        (':a :v "300"^^xsd:byte .', "dt-not-type"),
        (':a :v "abc"^^xsd:integer .', "dt-not-type"),
        (":v rdfs:range xsd:nonNegativeInteger . :a :v -3 .", "dt-not-type"),
        (":v rdfs:range xsd:string . :a :v 3 .", "dt-not-type"),
        (
            ":Age owl:equivalentClass xsd:nonNegativeInteger . :v rdfs:range :Age . :a :v -3 .",
            "dt-not-type",
        ),
        (":v a owl:FunctionalProperty . :a :v 5 , 6 .", "dt-diff"),
        (':v a owl:FunctionalProperty . :a :v "5"^^xsd:integer , "5.0E0"^^xsd:double .', "dt-diff"),
        # OWL 2's floating-point equality is identity: +0 and -0 are two values
        (':v a owl:FunctionalProperty . :a :v "+0.0"^^xsd:float , "-0.0"^^xsd:float .', "dt-diff"),
    ],
)
def test_literals_outside_their_datatype_or_equal_but_different_are_inconsistent(
    load: Loader, turtle: str, rule: str
) -> None:
    store = load(PREFIXES + turtle)
    report = is_consistent(store, asserted=ASSERTED, inferred=INFERRED)
    assert rule in {clash.rule for clash in report.clashes}, report.clashes


@pytest.mark.parametrize(
    "turtle",
    [
        ':a :v "NaN"^^xsd:double , "NaN"^^xsd:float , "-INF"^^xsd:double .',
        ':v a owl:FunctionalProperty . :a :v "0.0"^^xsd:double , "0"^^xsd:double .',
    ],
)
def test_nan_is_a_value_and_zeros_of_one_sign_are_equal(load: Loader, turtle: str) -> None:
    report = is_consistent(load(PREFIXES + turtle), asserted=ASSERTED, inferred=INFERRED)
    assert report.consistent, report.clashes


def test_literals_with_equal_values_are_the_same(load: Loader) -> None:  # dt-eq
    turtle = ':v a owl:FunctionalProperty . :a :v "5"^^xsd:byte , "5.0"^^xsd:decimal , 5 .'
    store = load(PREFIXES + turtle)
    assert is_consistent(store, asserted=ASSERTED, inferred=INFERRED).consistent
    store = load(PREFIXES + ':v rdfs:subPropertyOf :w . :a :v "5"^^xsd:byte . :b :w 5 .')
    materialise(store, asserted=ASSERTED, inferred=INFERRED)
    assert f'<{EX}a> <{EX}w> "5"^^<{XSD}integer>' in graph_triples(store)
