"""The W3C OWL 2 test cases marked for the RL profile (94 cases of the OWL Working Group's export,
vendored under ``owl2_w3c_rl/``), run against the engine in memory with the FZI suite's checker.

Each case is checked for every type it carries: a consistency test's premise is consistent, an
inconsistency test's is not, a positive entailment test's conclusion is entailed and a negative
entailment test's non-conclusion is not. A conclusion is entailed when its triples are in the
closure, blank nodes read as variables (the FZI suite's checker), leaving out its ontology
header (``x rdf:type owl:Ontology``, which names the document, not an axiom). Two individuals
are different when the closure says so or, as OWL defines it, when the premise with the two made
the same is inconsistent: so an ``owl:differentFrom`` or ``owl:AllDifferent`` conclusion is
checked by refutation, the way an OWL 2 RL reasoner answers such a question (the rules derive
``owl:differentFrom`` only through dt-diff). Every case passes but those in
:data:`EXPECTED_FAILURES`, each with its reason.
"""

import xml.etree.ElementTree as ElementTree
from dataclasses import dataclass
from pathlib import Path

import pyhornedowl
import pytest
from pyoxigraph import RdfFormat, parse

from reasoners.owl_rl import closure

from .conftest import Fact, entails

MANIFEST = Path(__file__).parent / "owl2_w3c_rl" / "profile-RL.rdf"
TEST = "{http://www.w3.org/2007/OWL/testOntology#}"
RDF = "{http://www.w3.org/1999/02/22-rdf-syntax-ns#}"
OWL = "http://www.w3.org/2002/07/owl#"
OWL_IMPORTS = f"<{OWL}imports>"
RDF_TYPE = "<http://www.w3.org/1999/02/22-rdf-syntax-ns#type>"
RDF_FIRST = "<http://www.w3.org/1999/02/22-rdf-syntax-ns#first>"
RDF_REST = "<http://www.w3.org/1999/02/22-rdf-syntax-ns#rest>"

_PROPERTY_AXIOM = (
    "out of RL's reach: the conclusion is a property axiom ({}); of property axioms the "
    "rules derive only subproperties, equivalences, domains and ranges (scm-*), never a "
    "disjointness, a characteristic or a chain"
)
_CLASS_EXPRESSION = (
    "out of RL's reach: the conclusion asserts {}, a class expression the OWL 2 RL/RDF rules "
    "never build (they derive facts and axioms between the classes a graph already names)"
)
_DIRECT_ANNOTATION = (
    "out of RL's reach: a Direct Semantics case (annotations carry no meaning there, so the "
    "conclusion's annotation of the equivalent class holds trivially); under the RDF-based "
    "semantics, which the rules implement, {} is not entailed"
)
_DATATYPE_SUBSUMPTION = (
    "out of RL's reach: {} follows from the datatypes' value spaces (an rdfs:range between "
    "datatypes); the rule tables derive no rdfs:subClassOf between datatypes (dt-type2 types "
    "literals by value instead)"
)
EXPECTED_FAILURES = {
    "Disjoint_Props_via_Disjoint_Domains": _PROPERTY_AXIOM.format(
        "sonOf owl:propertyDisjointWith daughterOf, from disjoint domains"
    ),
    "Disjoint_Props_via_Disjoint_Ranges": _PROPERTY_AXIOM.format(
        "a owl:propertyDisjointWith, from disjoint ranges"
    ),
    "New-Feature-ObjectPropertyChain-BJP-002": _PROPERTY_AXIOM.format(
        "the chain p o p -> p, from p owl:TransitiveProperty"
    ),
    "chain2trans1": _PROPERTY_AXIOM.format("p owl:TransitiveProperty, from the chain p o p -> p"),
    "DisjointClasses-001": _CLASS_EXPRESSION.format("Stewie rdf:type (owl:complementOf Girl)"),
    "DisjointClasses-003": _CLASS_EXPRESSION.format("membership of two complement classes"),
    "New-Feature-ObjectQCR-002": _CLASS_EXPRESSION.format(
        "Stewie rdf:type (owl:complementOf Woman), by a max-qualified-cardinality argument"
    ),
    "WebOnt-I5.26-010": _CLASS_EXPRESSION.format(
        "an owl:minCardinality 1 restriction (every property has one as a class)"
    ),
    "WebOnt-I5.5-005": _CLASS_EXPRESSION.format("the owl:unionOf of one class"),
    "New-Feature-ReflexiveProperty-001": (
        "out of RL's reach: owl:ReflexiveProperty is not in OWL 2 RL (Profiles 4.2.5 leaves out "
        "reflexive object property axioms) and no rule of the tables reads it"
    ),
    "WebOnt-I4.6-005-Direct": _DIRECT_ANNOTATION.format("C2 rdfs:comment"),
    "WebOnt-equivalentClass-008-Direct": _DIRECT_ANNOTATION.format("c2's annotation"),
    "WebOnt-I5.8-006": _DATATYPE_SUBSUMPTION.format("range xsd:short from range xsd:byte"),
    "WebOnt-I5.8-008": _DATATYPE_SUBSUMPTION.format(
        "range xsd:unsignedShort from ranges xsd:short and xsd:unsignedInt"
    ),
    "WebOnt-I5.8-009": _DATATYPE_SUBSUMPTION.format(
        "range xsd:short from ranges xsd:nonNegativeInteger and xsd:nonPositiveInteger (only 0)"
    ),
}


@dataclass(frozen=True)
class Document:
    """An ontology document of the manifest: its text, and whether it is in OWL functional
    syntax (``test:fs…``) rather than RDF/XML (``test:rdfXml…``)."""

    text: str
    functional: bool


@dataclass(frozen=True)
class Case:
    """One ``test:TestCase`` of the manifest."""

    identifier: str
    types: frozenset[str]
    premise: Document | None
    conclusion: Document | None
    non_conclusion: Document | None


def _text(element: ElementTree.Element, tag: str) -> str | None:
    child = element.find(TEST + tag)
    return None if child is None else child.text


def _document(element: ElementTree.Element, role: str) -> Document | None:
    """The case's ``role`` ontology (``PremiseOntology``...), in RDF/XML when the export has it."""
    rdf_xml = _text(element, "rdfXml" + role)
    if rdf_xml is not None:
        return Document(rdf_xml, functional=False)
    functional = _text(element, "fs" + role)
    return None if functional is None else Document(functional, functional=True)


def _manifest() -> tuple[list[Case], dict[str, Document]]:
    """The cases, and the imported ontologies' documents by ontology IRI."""
    root = ElementTree.parse(MANIFEST).getroot()
    cases = [
        Case(
            identifier=_text(element, "identifier") or "",
            types=frozenset(
                t.attrib[RDF + "resource"].removeprefix(TEST[1:-1])
                for t in element.findall(RDF + "type")
            ),
            premise=_document(element, "PremiseOntology"),
            conclusion=_document(element, "ConclusionOntology"),
            non_conclusion=_document(element, "NonConclusionOntology"),
        )
        for element in root.findall(TEST + "TestCase")
    ]
    imported = {}
    for element in root.findall("{http://www.w3.org/2002/07/owl#}Thing"):
        iri = element.find(TEST + "importedOntologyIRI")
        document = _text(element, "rdfXmlInputOntology")
        if iri is not None and document is not None:
            imported[f"<{iri.attrib[RDF + 'resource']}>"] = Document(document, functional=False)
    return cases, imported


CASES, IMPORTED = _manifest()


def _graph(document: Document) -> list[Fact]:
    """The document's triples; functional syntax is mapped to RDF by py-horned-owl (the OWL 2
    mapping to RDF graphs), as Engram's REASON reads RDF only."""
    text = document.text
    if document.functional:
        text = pyhornedowl.open_ontology_from_string(text, "ofn").save_to_string("rdf")
    return [
        (str(q.subject), str(q.predicate), str(q.object))
        for q in parse(text, format=RdfFormat.RDF_XML, base_iri="http://example.org/")
    ]


def _premise(case: Case) -> list[Fact]:
    """The premise graph with the graphs it imports (owl:imports of the manifest's documents)."""
    assert case.premise is not None, "no premise"
    facts = _graph(case.premise)
    for _, predicate, iri in list(facts):
        if predicate == OWL_IMPORTS and iri in IMPORTED:
            facts += _graph(IMPORTED[iri])
    return facts


def _members(facts: list[Fact], head: str) -> tuple[list[str], set[str]]:
    """The members of the RDF list at ``head``, and its cells."""
    by_subject = {(s, p): o for s, p, o in facts}
    members, cells = [], set()
    while (head, RDF_FIRST) in by_subject:
        members.append(by_subject[head, RDF_FIRST])
        cells.add(head)
        head = by_subject.get((head, RDF_REST), "")
    return members, cells


def _split(conclusion: list[Fact]) -> tuple[list[Fact], list[tuple[str, str]]]:
    """The conclusion's triples to find in the closure, and its pairs of different individuals
    (``owl:differentFrom``, and every two members of an ``owl:AllDifferent``, whose list cells
    leave the triples). The ontology header is left out."""
    headers = {s for s, p, o in conclusion if p == RDF_TYPE and o == f"<{OWL}Ontology>"}
    all_different = {s for s, p, o in conclusion if p == RDF_TYPE and o == f"<{OWL}AllDifferent>"}
    pairs: list[tuple[str, str]] = []
    cells: set[str] = set()
    for s, p, o in conclusion:
        if p == f"<{OWL}differentFrom>":
            pairs.append((s, o))
        elif s in all_different and p in (f"<{OWL}members>", f"<{OWL}distinctMembers>"):
            members, list_cells = _members(conclusion, o)
            pairs += [(a, b) for i, a in enumerate(members) for b in members[i + 1 :]]
            cells |= list_cells
    triples = [
        (s, p, o)
        for s, p, o in conclusion
        if s not in headers | all_different | cells and p != f"<{OWL}differentFrom>"
    ]
    return triples, pairs


def _different(premise: list[Fact], facts: set[Fact], a: str, b: str) -> bool:
    different = f"<{OWL}differentFrom>"
    if (a, different, b) in facts or (b, different, a) in facts:
        return True
    _, report = closure([*premise, (a, f"<{OWL}sameAs>", b)])
    return not report.consistent


def _entailed(premise: list[Fact], facts: set[Fact], conclusion: list[Fact]) -> bool:
    triples, pairs = _split(conclusion)
    return entails(facts, triples) and all(_different(premise, facts, a, b) for a, b in pairs)


REASONING = {
    "ConsistencyTest",
    "InconsistencyTest",
    "PositiveEntailmentTest",
    "NegativeEntailmentTest",
}


def _params() -> list[object]:
    params: list[object] = []
    for case in CASES:
        reason = EXPECTED_FAILURES.get(case.identifier)
        marks = [pytest.mark.xfail(reason=reason, strict=True)] if reason else []
        if not case.types & REASONING:
            marks = [pytest.mark.skip(reason="a profile identification test only: no reasoning")]
        params.append(pytest.param(case, id=case.identifier, marks=marks))
    return params


def test_the_manifest_holds_the_rl_cases() -> None:
    assert len(CASES) == 94
    assert all(case.premise is not None for case in CASES if case.types & REASONING)
    assert set(EXPECTED_FAILURES) <= {case.identifier for case in CASES}


@pytest.mark.parametrize("case", _params())
def test_case(case: Case) -> None:
    premise = _premise(case)
    facts, report = closure(premise)
    if "InconsistencyTest" in case.types:
        assert not report.consistent, "found consistent"
    if "ConsistencyTest" in case.types:
        assert report.consistent, f"found inconsistent: {report}"
    if "PositiveEntailmentTest" in case.types:
        assert case.conclusion is not None, "no conclusion"
        assert _entailed(premise, facts, _graph(case.conclusion)), "conclusion not entailed"
    if "NegativeEntailmentTest" in case.types:
        assert case.non_conclusion is not None, "no non-conclusion"
        non_conclusion = _graph(case.non_conclusion)
        assert not _entailed(premise, facts, non_conclusion), "non-conclusion entailed"
