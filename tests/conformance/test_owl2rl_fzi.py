"""The FZI OWL 2 RL/RDF conformance suite (Schneider & Mainzer, 273 cases, vendored under
``owl2rl/cases``), run against the engine in memory: every case passes but those listed in
:data:`EXPECTED_FAILURES`, each with its reason."""

import re
from pathlib import Path

import pytest

from .conftest import passes, triples

CASES = Path(__file__).parent / "owl2rl" / "cases"
_EQ_REF = (
    "eq-ref: x owl:sameAs x holds for every term and is never recorded (docs/owl-rl.md, "
    "'What is left out')"
)
EXPECTED_FAILURES = {
    "rdfbased-ont-graph-allsame": _EQ_REF,
    "rdfbased-sem-eqdis-sameas-rflxv": _EQ_REF,
    "rdfbased-xtr-reflection-selfsame": _EQ_REF,
}


def _kind(case: Path) -> str:
    metadata = (case / f"{case.name}.metadata.properties").read_text()
    found = re.search(r'key="testcase.type">([^<]*)<', metadata)
    assert found is not None, case
    return found.group(1)


def _params() -> list[object]:
    params: list[object] = []
    for case in sorted(CASES.iterdir()):
        reason = EXPECTED_FAILURES.get(case.name)
        marks = [pytest.mark.xfail(reason=reason, strict=True)] if reason else []
        params.append(pytest.param(case, id=case.name, marks=marks))
    return params


def test_the_suite_is_complete() -> None:
    assert len(list(CASES.iterdir())) == 273
    assert set(EXPECTED_FAILURES) <= {case.name for case in CASES.iterdir()}


@pytest.mark.parametrize("case", _params())
def test_case(case: Path) -> None:
    kind = _kind(case)
    if kind == "INCONSISTENCY":
        assert passes(triples(case / f"{case.name}.graph.ttl"), None), "found consistent"
    else:
        assert kind == "POSITIVE_ENTAILMENT"
        premise = triples(case / f"{case.name}.premisegraph.ttl")
        conclusion = triples(case / f"{case.name}.conclusiongraph.ttl")
        assert passes(premise, conclusion), "conclusion not entailed"
