"""DL-safe SWRL rules carried by the ontology, as Protégé writes them, with swrlb built-ins."""

import pytest
from pyoxigraph import Literal, NamedNode, RdfFormat

from ontologies.vocab import RDF_TYPE
from reasoners.owl_rl import SwrlRuleError, materialise

from .conftest import ASSERTED, INFERRED, Loader, graph_triples

NS = "http://example.org/family#"
XSD = "http://www.w3.org/2001/XMLSchema#"
SWRL = "http://www.w3.org/2003/11/swrl#"
SWRLB = "http://www.w3.org/2003/11/swrlb#"
RDF = "http://www.w3.org/1999/02/22-rdf-syntax-ns#"


def _atom_list(*atoms: str) -> str:
    if not atoms:
        return ""
    head, *rest = atoms
    tail = (
        f"<rdf:rest>{_atom_list(*rest)}</rdf:rest>"
        if rest
        else f'<rdf:rest rdf:resource="{RDF}nil"/>'
    )
    return (
        f'<rdf:Description><rdf:type rdf:resource="{SWRL}AtomList"/>'
        f"<rdf:first>{head}</rdf:first>{tail}</rdf:Description>"
    )


def _class_atom(cls: str, var: str) -> str:
    return (
        f'<rdf:Description><rdf:type rdf:resource="{SWRL}ClassAtom"/>'
        f'<swrl:classPredicate rdf:resource="{NS}{cls}"/>'
        f'<swrl:argument1 rdf:resource="urn:swrl:var#{var}"/></rdf:Description>'
    )


def _property_atom(kind: str, prop: str, var1: str, var2: str) -> str:
    return (
        f'<rdf:Description><rdf:type rdf:resource="{SWRL}{kind}"/>'
        f'<swrl:propertyPredicate rdf:resource="{NS}{prop}"/>'
        f'<swrl:argument1 rdf:resource="urn:swrl:var#{var1}"/>'
        f'<swrl:argument2 rdf:resource="urn:swrl:var#{var2}"/></rdf:Description>'
    )


def _builtin(name: str, *args: str) -> str:
    """``args``: ``?v`` for a variable, ``17`` for an xsd:integer literal."""
    return (
        f'<rdf:Description><rdf:type rdf:resource="{SWRL}BuiltinAtom"/>'
        f'<swrl:builtin rdf:resource="{SWRLB}{name}"/>'
        f"<swrl:arguments>{_literal_list(*args)}</swrl:arguments></rdf:Description>"
    )


def _literal_list(*args: str) -> str:
    head, *rest = args
    first = (
        f'<rdf:first rdf:resource="urn:swrl:var#{head[1:]}"/>'
        if head.startswith("?")
        else f'<rdf:first rdf:datatype="{XSD}integer">{head}</rdf:first>'
    )
    tail = (
        f"<rdf:rest>{_literal_list(*rest)}</rdf:rest>"
        if rest
        else f'<rdf:rest rdf:resource="{RDF}nil"/>'
    )
    return f"<rdf:Description>{first}{tail}</rdf:Description>"


def _ontology(*rules: tuple[list[str], list[str]], variables: str = "p a n") -> str:
    declared = "".join(
        f'<rdf:Description rdf:about="urn:swrl:var#{v}"><rdf:type rdf:resource="{SWRL}Variable"/>'
        "</rdf:Description>"
        for v in variables.split()
    )
    imps = "".join(
        f'<rdf:Description><rdf:type rdf:resource="{SWRL}Imp"/>'
        f"<swrl:body>{_atom_list(*body)}</swrl:body><swrl:head>{_atom_list(*head)}</swrl:head>"
        "</rdf:Description>"
        for body, head in rules
    )
    return f"""<?xml version="1.0"?>
<rdf:RDF xmlns:rdf="{RDF}" xmlns:rdfs="http://www.w3.org/2000/01/rdf-schema#"
    xmlns:owl="http://www.w3.org/2002/07/owl#" xmlns:swrl="{SWRL}" xmlns:swrlb="{SWRLB}">
  <owl:Ontology rdf:about="{NS[:-1]}"/>
  <owl:DatatypeProperty rdf:about="{NS}hasAge"/>
  <owl:Class rdf:about="{NS}Adult"><rdfs:subClassOf rdf:resource="{NS}Person"/></owl:Class>
  {declared}{imps}
</rdf:RDF>"""


ADULT_RULE = (
    [
        _class_atom("Person", "p"),
        _property_atom("DatavaluedPropertyAtom", "hasAge", "p", "a"),
        _builtin("greaterThan", "?a", "17"),
    ],
    [_class_atom("Adult", "p")],
)
NEXT_AGE_RULE = (
    [
        _property_atom("DatavaluedPropertyAtom", "hasAge", "p", "a"),
        _builtin("add", "?n", "?a", "1"),
    ],
    [_property_atom("DatavaluedPropertyAtom", "nextAge", "p", "n")],
)


def _person(store, name: str, age: int) -> None:  # type: ignore[no-untyped-def]
    with store.transaction() as tx:
        tx.insert(NamedNode(NS + name), RDF_TYPE, NamedNode(NS + "Person"), ASSERTED)
        tx.insert(
            NamedNode(NS + name),
            NamedNode(NS + "hasAge"),
            Literal(str(age), datatype=NamedNode(XSD + "integer")),
            ASSERTED,
        )


def test_protege_rdfxml_rule_with_comparison_and_arithmetic(load: Loader) -> None:
    store = load(_ontology(ADULT_RULE, NEXT_AGE_RULE), RdfFormat.RDF_XML)
    _person(store, "ann", 34)
    _person(store, "tim", 12)
    materialise(store, asserted=ASSERTED, inferred=INFERRED)
    inferred = graph_triples(store)
    adult = f"<{RDF}type> <{NS}Adult>"
    assert f"<{NS}ann> {adult}" in inferred
    assert f"<{NS}tim> {adult}" not in inferred
    assert f'<{NS}ann> <{NS}nextAge> "35"^^<{XSD}integer>' in inferred
    assert f'<{NS}tim> <{NS}nextAge> "13"^^<{XSD}integer>' in inferred

    _person(store, "eve", 40)  # an incremental REASON runs the rules on the new facts
    report = materialise(store, asserted=ASSERTED, inferred=INFERRED)
    assert report.incremental
    assert f"<{NS}eve> {adult}" in graph_triples(store)
    assert f'<{NS}eve> <{NS}nextAge> "41"^^<{XSD}integer>' in graph_triples(store)


TURTLE_RULE = f"""
@prefix : <{NS}> . @prefix swrl: <{SWRL}> . @prefix rdf: <{RDF}> .
@prefix owl: <http://www.w3.org/2002/07/owl#> .
<urn:swrl:var#r> a swrl:Variable . <urn:swrl:var#l> a swrl:Variable .
<urn:swrl:var#d> a swrl:Variable .
[ a swrl:Imp ;
  swrl:body ( [ a swrl:ClassAtom ; swrl:classPredicate :Robot ; swrl:argument1 <urn:swrl:var#r> ]
              [ a swrl:IndividualPropertyAtom ; swrl:propertyPredicate :isIn ;
                swrl:argument1 <urn:swrl:var#r> ; swrl:argument2 <urn:swrl:var#l> ]
              [ a swrl:IndividualPropertyAtom ; swrl:propertyPredicate :connectedTo ;
                swrl:argument1 <urn:swrl:var#l> ; swrl:argument2 <urn:swrl:var#d> ] ) ;
  swrl:head ( [ a swrl:IndividualPropertyAtom ; swrl:propertyPredicate :canReach ;
                swrl:argument1 <urn:swrl:var#r> ; swrl:argument2 <urn:swrl:var#d> ] ) ] .
:connectedTo a owl:SymmetricProperty .
:robot1 a :Robot ; :isIn :room1 . :corridor :connectedTo :room1 . :room1 :connectedTo :room2 .
:human :isIn :room1 .
"""


def test_turtle_rule_joins_with_owl_consequences(load: Loader) -> None:
    store = load(TURTLE_RULE)
    materialise(store, asserted=ASSERTED, inferred=INFERRED)
    reach = {t for t in graph_triples(store) if f"<{NS}canReach>" in t}
    assert reach == {
        f"<{NS}robot1> <{NS}canReach> <{NS}corridor>",  # via the symmetric connectedTo
        f"<{NS}robot1> <{NS}canReach> <{NS}room2>",
    }


@pytest.mark.parametrize(
    ("rule", "message"),
    [
        (
            (
                [_class_atom("Person", "p"), _builtin("sin", "?n", "?p")],
                [_class_atom("Adult", "p")],
            ),
            "swrlb#sin> is not supported",
        ),
        (
            (
                [_class_atom("Person", "p")],
                [_property_atom("IndividualPropertyAtom", "knows", "p", "n")],
            ),
            "DL-safe",
        ),
    ],
)
def test_unsupported_or_unsafe_rule_is_refused_and_changes_nothing(
    load: Loader, rule: tuple[list[str], list[str]], message: str
) -> None:
    store = load(_ontology(rule), RdfFormat.RDF_XML)
    with pytest.raises(SwrlRuleError, match=message):
        materialise(store, asserted=ASSERTED, inferred=INFERRED)
    assert graph_triples(store) == set()


def _builtin_rule(builtin: str, a: str, b: str, *, compare: bool) -> str:
    """``:x :a ?a . :x :b ?b . swrlb:<builtin>(...) -> :x :r ?r`` (or ``-> :x a :Yes``)."""
    args = (
        "( <urn:swrl:var#a> <urn:swrl:var#b> )"
        if compare
        else ("( <urn:swrl:var#r> <urn:swrl:var#a> <urn:swrl:var#b> )")
    )
    head = (
        "[ a swrl:ClassAtom ; swrl:classPredicate :Yes ; swrl:argument1 <urn:swrl:var#x> ]"
        if compare
        else "[ a swrl:DatavaluedPropertyAtom ; swrl:propertyPredicate :r ;"
        " swrl:argument1 <urn:swrl:var#x> ; swrl:argument2 <urn:swrl:var#r> ]"
    )
    return f"""
@prefix : <{NS}> . @prefix swrl: <{SWRL}> . @prefix swrlb: <{SWRLB}> .
@prefix xsd: <{XSD}> .
<urn:swrl:var#x> a swrl:Variable . <urn:swrl:var#a> a swrl:Variable .
<urn:swrl:var#b> a swrl:Variable . <urn:swrl:var#r> a swrl:Variable .
[ a swrl:Imp ;
  swrl:body (
    [ a swrl:DatavaluedPropertyAtom ; swrl:propertyPredicate :a ;
      swrl:argument1 <urn:swrl:var#x> ; swrl:argument2 <urn:swrl:var#a> ]
    [ a swrl:DatavaluedPropertyAtom ; swrl:propertyPredicate :b ;
      swrl:argument1 <urn:swrl:var#x> ; swrl:argument2 <urn:swrl:var#b> ]
    [ a swrl:BuiltinAtom ; swrl:builtin swrlb:{builtin} ; swrl:arguments {args} ] ) ;
  swrl:head ( {head} ) ] .
:x :a {a} ; :b {b} .
"""


@pytest.mark.parametrize(
    ("builtin", "a", "b", "expected"),
    [
        ("add", "2", "3", f'"5"^^<{XSD}integer>'),
        ("subtract", "2", "3.5", f'"-1.5"^^<{XSD}decimal>'),
        ("multiply", "2", '"1.5"^^xsd:double', f'"3"^^<{XSD}double>'),
        ("divide", "7", "2", f'"3.5"^^<{XSD}decimal>'),
        ("integerDivide", "7", "2", f'"3"^^<{XSD}integer>'),
        ("mod", "7", "3", f'"1"^^<{XSD}integer>'),
        ("pow", "2", "10", f'"1024"^^<{XSD}integer>'),
        ("stringConcat", '"robo"', '"t"', '"robot"'),
        ("divide", "1", "0", None),  # no value: the rule does not fire
    ],
)
def test_arithmetic_builtins_bind_their_first_argument(
    load: Loader, builtin: str, a: str, b: str, expected: str | None
) -> None:
    store = load(_builtin_rule(builtin, a, b, compare=False))
    materialise(store, asserted=ASSERTED, inferred=INFERRED)
    values = {t.split(" ", 2)[2] for t in graph_triples(store) if f"<{NS}r>" in t}
    assert values == ({expected} if expected else set())


@pytest.mark.parametrize(
    ("builtin", "a", "b", "holds"),
    [
        ("lessThan", "2", '"2.5"^^xsd:double', True),
        ("lessThan", "3", "2.5", False),
        ("lessThanOrEqual", "2", "2.0", True),
        ("greaterThan", '"0.75"^^xsd:double', "0.5", True),
        ("greaterThanOrEqual", "1", "2", False),
        ("equal", "1", '"1.0"^^xsd:double', True),
        ("notEqual", '"a"', '"b"', True),
        ("equal", '"a"', "1", False),
        ("startsWith", '"robot arm"', '"robot"', True),
        ("contains", '"robot arm"', '"arm"', True),
    ],
)
def test_comparison_builtins_filter(
    load: Loader, builtin: str, a: str, b: str, holds: bool
) -> None:
    store = load(_builtin_rule(builtin, a, b, compare=True))
    materialise(store, asserted=ASSERTED, inferred=INFERRED)
    assert (f"<{NS}x> <{RDF}type> <{NS}Yes>" in graph_triples(store)) is holds


def _rule(body: str, head: str, variables: str) -> str:
    """A Turtle SWRL rule; atoms are written ``Class(?x)``, ``prop(?x, ?y)``,
    ``sameAs(?x, ?y)`` or ``differentFrom(?x, ?y)`` over variables named in ``variables``."""

    def atom(text: str) -> str:
        name, args = text.strip().rstrip(")").split("(")
        terms = [f"<urn:swrl:var#{a.strip()[1:]}>" for a in args.split(",")]
        if len(terms) == 1:
            return f"[ a swrl:ClassAtom ; swrl:classPredicate :{name} ; swrl:argument1 {terms[0]} ]"
        kind = {"sameAs": "SameIndividualAtom", "differentFrom": "DifferentIndividualsAtom"}
        pair = f"swrl:argument1 {terms[0]} ; swrl:argument2 {terms[1]}"
        if name in kind:
            return f"[ a swrl:{kind[name]} ; {pair} ]"
        return f"[ a swrl:IndividualPropertyAtom ; swrl:propertyPredicate :{name} ; {pair} ]"

    declared = " ".join(f"<urn:swrl:var#{v}> a swrl:Variable ." for v in variables.split())
    atoms = [
        " ".join(atom(a.strip(" ,") + ")") for a in part.split(")") if a.strip(" ,"))
        for part in (body, head)
    ]
    return (
        f"@prefix : <{NS}> . @prefix swrl: <{SWRL}> . "
        f"@prefix owl: <http://www.w3.org/2002/07/owl#> . {declared} "
        f"[ a swrl:Imp ; swrl:body ( {atoms[0]} ) ; swrl:head ( {atoms[1]} ) ] .\n"
    )


CONNECTED_RULE = _rule(
    "hasDoor(?r, ?d), hasDoor(?s, ?d), differentFrom(?r, ?s)", "connectedTo(?r, ?s)", "r s d"
)
"""The connectivity rule of the robot-surveillance assignments written for ARMOR."""
ROOMS = ":r1 :hasDoor :d1 . :r2 :hasDoor :d1 , :d2 . :r3 :hasDoor :d2 .\n"


def _connected(store) -> set[tuple[str, str]]:  # type: ignore[no-untyped-def]
    materialise(store, asserted=ASSERTED, inferred=INFERRED)
    found = [t.split() for t in graph_triples(store) if f"<{NS}connectedTo>" in t]
    return {(s[len(NS) + 1 : -1], o[len(NS) + 1 : -1]) for s, _, o in found}


@pytest.mark.parametrize(
    "different",
    [
        "[] a owl:AllDifferent ; owl:distinctMembers ( :r1 :r2 :r3 ) .",
        "[] a owl:AllDifferent ; owl:members ( :r1 :r2 :r3 ) .",
        ":r1 owl:differentFrom :r2 . :r3 owl:differentFrom :r2 .",
    ],
)
def test_different_individuals_atom_holds_for_all_different_and_both_directions(
    load: Loader, different: str
) -> None:
    store = load(CONNECTED_RULE + ROOMS + different)
    pairs = {("r1", "r2"), ("r2", "r1"), ("r2", "r3"), ("r3", "r2")}
    assert _connected(store) == pairs


@pytest.mark.parametrize(
    ("different", "pairs"),
    [
        (
            "[] a owl:AllDifferent ; owl:distinctMembers ( :r1 :r2 :r3 ) .",
            {("r1", "r2"), ("r2", "r1"), ("r2", "r3"), ("r3", "r2")},
        ),
        (":r1 owl:differentFrom :r2 .", {("r1", "r2"), ("r2", "r1")}),
    ],
)
def test_differences_added_after_a_reason_fire_the_rule_incrementally(
    load: Loader, different: str, pairs: set[tuple[str, str]]
) -> None:
    store = load(CONNECTED_RULE + ROOMS)
    assert _connected(store) == set()
    with store.transaction() as tx:
        tx.load(
            f"@prefix : <{NS}> . @prefix owl: <http://www.w3.org/2002/07/owl#> . {different}",
            format=RdfFormat.TURTLE,
            graph=ASSERTED,
        )
    assert _connected(store) == pairs


def test_same_individual_atom_holds_for_a_term_and_itself(load: Loader) -> None:
    rule = _rule("isIn(?r, ?l), owns(?o, ?m), sameAs(?l, ?m)", "visits(?r, ?o)", "r l o m")
    store = load(rule + ":robot :isIn :room1 . :ann :owns :room1 . :bob :owns :room2 .")
    materialise(store, asserted=ASSERTED, inferred=INFERRED)
    visits = {t for t in graph_triples(store) if f"<{NS}visits>" in t}
    assert visits == {f"<{NS}robot> <{NS}visits> <{NS}ann>"}
