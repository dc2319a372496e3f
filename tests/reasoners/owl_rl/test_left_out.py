"""What REASON leaves out of the inferred graph on purpose (docs/owl-rl.md): each item here is
checked to stay out, so that a change to it is a decision, not an accident."""

from reasoners.owl_rl import closure, materialise

from .conftest import ASSERTED, INFERRED, Loader, graph_triples
from .test_owlrl_parity import PREFIXES

SAME = "<http://www.w3.org/2002/07/owl#sameAs>"
DIFFERENT = "<http://www.w3.org/2002/07/owl#differentFrom>"
TYPE = "<http://www.w3.org/1999/02/22-rdf-syntax-ns#type>"
XSD = "http://www.w3.org/2001/XMLSchema#"
BYTE = f'"5"^^<{XSD}byte>'


def test_eq_ref_x_same_as_x_is_never_written(load: Loader) -> None:
    store = load(PREFIXES + ":a :p :b . :a owl:sameAs :c .")
    materialise(store, asserted=ASSERTED, inferred=INFERRED)
    same = [t.split() for t in graph_triples(store) if SAME in t]
    assert same and not [t for t in same if t[0] == t[2]]


def test_literal_subjects_stay_inside_the_engine(load: Loader) -> None:
    store = load(
        PREFIXES + ':a :v "5"^^xsd:byte . :C owl:equivalentClass [ a owl:Restriction ; '
        "owl:onProperty :v ; owl:someValuesFrom xsd:short ] ."
    )
    materialise(store, asserted=ASSERTED, inferred=INFERRED)
    assert not [t for t in graph_triples(store) if t.startswith('"')]
    facts, _ = closure([("<a>", "<v>", BYTE)])
    assert (BYTE, TYPE, f"<{XSD}byte>") not in facts  # no rule names xsd:byte: not typed
    facts, _ = closure([("<a>", "<v>", BYTE), ("<b>", "<v>", '"5"^^<' + XSD + "integer>")])
    assert (BYTE, SAME, '"5"^^<' + XSD + "integer>") in facts  # dt-eq, kept inside
    assert (BYTE, TYPE, f"<{XSD}byte>") in facts  # the same as a term: typed for eq-rep


def test_dt_diff_is_written_only_for_literals_that_are_the_same_as_something() -> None:
    facts, report = closure([("<a>", "<v>", '"1"'), ("<b>", "<v>", '"2"')])
    assert report.consistent and not [f for f in facts if f[1] == DIFFERENT]
    facts, _ = closure([("<a>", SAME, '"1"'), ("<b>", SAME, '"2"')])
    assert ("<a>", DIFFERENT, "<b>") in facts


def test_owlrl_datatype_disjointness_axioms_are_not_produced(load: Loader) -> None:
    store = load(PREFIXES + ":a :v 1 .")
    materialise(store, asserted=ASSERTED, inferred=INFERRED)
    assert not [t for t in graph_triples(store) if "disjointWith" in t]
