"""The OWL 2 RL inconsistency rules: each clash is found and named, consistent data has none."""

import pytest

from reasoners.owl_rl import is_consistent, materialise

from .conftest import ASSERTED, INFERRED, Loader
from .test_owlrl_parity import PREFIXES

CLASHES = [
    ("cls-nothing2", ":a a owl:Nothing .", "<http://example.org/a>"),
    ("cls-nothing2", ":A rdfs:subClassOf owl:Nothing . :a a :A .", "owl:Nothing"),
    (
        "cax-dw",
        ":Cube owl:disjointWith :Sphere . :Die rdfs:subClassOf :Cube . :a a :Die , :Sphere .",
        "<http://example.org/Sphere>",
    ),
    (
        "cax-adc",
        "[] a owl:AllDisjointClasses ; owl:members ( :A :B :C ) . :a a :A , :C .",
        "<http://example.org/C>",
    ),
    ("cls-com", ":Open owl:complementOf :Closed . :d a :Open , :Closed .", "complement"),
    ("eq-diff1", ":r1 owl:sameAs :r2 . :r2 owl:differentFrom :r1 .", "same and different"),
    (
        "eq-diff2",
        "[] a owl:AllDifferent ; owl:members ( :a :b :c ) . :c owl:sameAs :a .",
        "all-different",
    ),
    (
        "eq-diff3",
        (
            "[] a owl:AllDifferent ; owl:distinctMembers ( :a :b ) . :id a "
            "owl:InverseFunctionalProperty . :a :id 1 . :b :id 1 ."
        ),
        "all-different",
    ),
    ("prp-irp", ":partOf a owl:IrreflexiveProperty . :a :partOf :a .", "irreflexive"),
    ("prp-asyp", ":above a owl:AsymmetricProperty . :a :above :b . :b :above :a .", "asymmetric"),
    (
        "prp-asyp",
        ":above a owl:AsymmetricProperty ; owl:inverseOf :below . :a :above :b . :a :below :b .",
        "asymmetric",
    ),
    (
        "prp-pdw",
        ":leftOf owl:propertyDisjointWith :rightOf . :a :leftOf :b ; :rightOf :b .",
        "disjoint properties",
    ),
    (
        "prp-adp",
        "[] a owl:AllDisjointProperties ; owl:members ( :p :q ) . :a :p :b ; :q :b .",
        "disjoint properties",
    ),
    (
        "prp-npa1",
        (
            "[] a owl:NegativePropertyAssertion ; owl:sourceIndividual :a ; "
            "owl:assertionProperty :near ; owl:targetIndividual :b . :b :near :a . :near a "
            "owl:SymmetricProperty ."
        ),
        "asserted not to",
    ),
    (
        "prp-npa2",
        (
            "[] a owl:NegativePropertyAssertion ; owl:sourceIndividual :a ; "
            "owl:assertionProperty :level ; owl:targetValue 2 . :a :level 2 ."
        ),
        "asserted not to",
    ),
    ("eq-diff1", ":x owl:differentFrom :x .", "same and different"),
    ("prp-pdw", ":near owl:propertyDisjointWith :near . :a :near :b .", "disjoint properties"),
    (
        "prp-adp",
        "[] a owl:AllDisjointProperties ; owl:members ( :p :q :p ) . :a :p :b .",
        "disjoint properties",
    ),
    (
        "prp-npa1",
        (
            "[] owl:sourceIndividual :a ; owl:assertionProperty :near ; "
            "owl:targetIndividual :b . :a :near :b ."
        ),
        "asserted not to",
    ),
    (
        "prp-npa2",
        (
            "[] owl:sourceIndividual :a ; owl:assertionProperty :level ; owl:targetValue 2 . "
            ":a :level 2 ."
        ),
        "asserted not to",
    ),
    (
        "cls-maxc1",
        (
            ":Empty owl:equivalentClass [ a owl:Restriction ; owl:onProperty :holds ; "
            'owl:maxCardinality "0"^^xsd:nonNegativeInteger ] . :box a :Empty ; :holds :ball .'
        ),
        "at most 0",
    ),
    (
        "cls-maxqc1",
        (
            ":NoCup owl:equivalentClass [ a owl:Restriction ; owl:onProperty :holds ; "
            'owl:maxQualifiedCardinality "0"^^xsd:nonNegativeInteger ; owl:onClass :Cup ] . '
            ":tray a :NoCup ; :holds :c . :c a :Cup ."
        ),
        "at most 0",
    ),
]


@pytest.mark.parametrize(("rule", "turtle", "fragment"), CLASHES)
def test_each_inconsistency_rule_is_named(
    load: Loader, rule: str, turtle: str, fragment: str
) -> None:
    store = load(PREFIXES + turtle)
    report = is_consistent(store, asserted=ASSERTED, inferred=INFERRED)
    assert not report.consistent
    assert rule in {clash.rule for clash in report.clashes}
    assert any(fragment in str(clash) for clash in report.clashes), report.clashes
    reasoned = materialise(store, asserted=ASSERTED, inferred=INFERRED)
    assert not reasoned.consistent and reasoned.clashes == report.clashes


def test_consistent_data_has_no_clash(load: Loader) -> None:
    store = load(
        PREFIXES
        + """:Cube owl:disjointWith :Sphere . :a a :Cube . :b a :Sphere .
        :above a owl:AsymmetricProperty . :a :above :b . :a owl:differentFrom :b .
        :Empty owl:equivalentClass [ a owl:Restriction ; owl:onProperty :holds ;
                                     owl:maxCardinality "0"^^xsd:nonNegativeInteger ] .
        :c :holds :d ."""
    )
    assert is_consistent(store, asserted=ASSERTED, inferred=INFERRED).consistent
    assert materialise(store, asserted=ASSERTED, inferred=INFERRED).consistent


def test_incremental_reason_detects_a_new_clash_and_is_consistent_reads_the_state(
    load: Loader,
) -> None:
    store = load(
        PREFIXES + ":Cube owl:disjointWith :Sphere . :Die rdfs:subClassOf :Cube . :a a :Sphere ."
    )
    assert materialise(store, asserted=ASSERTED, inferred=INFERRED).consistent
    store_text = PREFIXES + ":a a :Die ."
    with store.transaction() as tx:
        from pyoxigraph import RdfFormat

        tx.load(store_text, format=RdfFormat.TURTLE, graph=ASSERTED)
    report = materialise(store, asserted=ASSERTED, inferred=INFERRED)
    assert report.incremental and not report.consistent
    assert [c.rule for c in report.clashes] == ["cax-dw"]
    assert is_consistent(store, asserted=ASSERTED, inferred=INFERRED).clashes == report.clashes
