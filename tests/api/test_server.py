"""The HTTP service through a real server on loopback: health, the SPARQL 1.1 Protocol,
export, and the write guard."""

import csv
import io
import json
from collections.abc import Callable
from pathlib import Path

import pytest
import rdflib
from SPARQLWrapper import JSON, SPARQLWrapper

from ontologies.vocab import SPHERE
from tests.conftest import LiveServer

COUNT_CLASSES = (
    "PREFIX owl: <http://www.w3.org/2002/07/owl#> SELECT (COUNT(?c) AS ?n) WHERE { ?c a owl:Class }"
)
SPHERE_LABEL = (
    "PREFIX rdfs: <http://www.w3.org/2000/01/rdf-schema#> "
    f"SELECT ?label WHERE {{ <{SPHERE.value}> rdfs:label ?label }}"
)
SLOW = "SELECT (COUNT(*) AS ?n) WHERE { ?a ?b ?c . ?d ?e ?f . ?g ?h ?i . ?j ?k ?l }"


def _class_count(body: bytes) -> int:
    return int(json.loads(body)["results"]["bindings"][0]["n"]["value"])


def test_health_reports_the_ontology_version(live_server: LiveServer) -> None:
    answer = live_server.client.get("/health")
    assert answer.status_code == 200
    assert answer.json()["status"] == "ok"
    assert answer.json()["ontology_version"].startswith("https://w3id.org/engram/ontology/")


@pytest.mark.parametrize(
    "send",
    [
        lambda c: c.get("/sparql", params={"query": COUNT_CLASSES}),
        lambda c: c.post("/sparql", data={"query": COUNT_CLASSES}),
        lambda c: c.post(
            "/sparql", content=COUNT_CLASSES, headers={"Content-Type": "application/sparql-query"}
        ),
    ],
    ids=["get", "post-form", "post-direct"],
)
def test_each_request_form_answers_sparql_json(live_server: LiveServer, send: Callable) -> None:
    answer = send(live_server.client)
    assert answer.status_code == 200
    assert answer.headers["content-type"].startswith("application/sparql-results+json")
    assert _class_count(answer.content) > 10


@pytest.mark.parametrize(
    ("query", "accept", "media_type"),
    [
        (SPHERE_LABEL, "application/sparql-results+xml", "application/sparql-results+xml"),
        (SPHERE_LABEL, "text/csv", "text/csv"),
        (SPHERE_LABEL, "text/tab-separated-values", "text/tab-separated-values"),
        ("ASK { ?s ?p ?o }", "application/sparql-results+json", "application/sparql-results+json"),
        ("CONSTRUCT WHERE { ?s a ?o } LIMIT 5", "text/turtle", "text/turtle"),
        ("CONSTRUCT WHERE { ?s a ?o } LIMIT 5", "application/n-triples", "application/n-triples"),
        ("CONSTRUCT WHERE { ?s a ?o } LIMIT 5", "application/rdf+xml", "application/rdf+xml"),
    ],
)
def test_content_negotiation(
    live_server: LiveServer, query: str, accept: str, media_type: str
) -> None:
    answer = live_server.client.get("/sparql", params={"query": query}, headers={"Accept": accept})
    assert answer.status_code == 200
    assert answer.headers["content-type"].split(";")[0] == media_type
    if media_type == "text/csv":
        rows = list(csv.reader(io.StringIO(answer.text)))
        assert rows == [["label"], ["sphere"]]
    if media_type in {"text/turtle", "application/n-triples", "application/rdf+xml"}:
        graph = rdflib.Graph().parse(data=answer.content, format=media_type)
        assert len(graph) == 5


def test_sparqlwrapper_reads_the_endpoint(live_server: LiveServer) -> None:
    endpoint = SPARQLWrapper(live_server.url + "/sparql")
    endpoint.setQuery(SPHERE_LABEL)
    endpoint.setReturnFormat(JSON)
    result = endpoint.query().convert()
    assert isinstance(result, dict)
    assert [row["label"]["value"] for row in result["results"]["bindings"]] == ["sphere"]


@pytest.mark.parametrize(
    ("request_args", "status", "fragment"),
    [
        ({"params": {"query": "SELEC ?x WHERE {}"}}, 400, "not a valid SPARQL query"),
        ({"params": {"query": "INSERT DATA { <a:b> <a:c> <a:d> }"}}, 400, "not a valid SPARQL"),
        ({"params": {"update": "INSERT DATA { <a:b> <a:c> <a:d> }"}}, 403, "read-only"),
        ({"params": {}}, 400, "query: expected exactly one value, got 0"),
        (
            {"params": {"query": "SELECT * WHERE { SERVICE <http://x/> { ?s ?p ?o } }"}},
            403,
            "SERVICE",
        ),
        (
            {"params": {"query": SPHERE_LABEL}, "headers": {"Accept": "image/png"}},
            406,
            "image/png",
        ),
    ],
    ids=["syntax", "update-as-query", "update-param", "no-query", "service", "not-acceptable"],
)
def test_bad_requests_get_clear_errors(
    live_server: LiveServer, request_args: dict, status: int, fragment: str
) -> None:
    answer = live_server.client.get("/sparql", **request_args)
    assert answer.status_code == status
    assert fragment in answer.json()["detail"]


def test_a_posted_update_is_refused_and_changes_nothing(live_server: LiveServer) -> None:
    before = _class_count(
        live_server.client.get("/sparql", params={"query": COUNT_CLASSES}).content
    )
    answer = live_server.client.post(
        "/sparql",
        content="INSERT DATA { GRAPH <a:g> { <a:x> a <http://www.w3.org/2002/07/owl#Class> } }",
        headers={"Content-Type": "application/sparql-update"},
    )
    assert answer.status_code == 403
    after = _class_count(live_server.client.get("/sparql", params={"query": COUNT_CLASSES}).content)
    assert after == before


@pytest.mark.slow
def test_a_query_over_the_time_limit_is_stopped(start_server: Callable[..., LiveServer]) -> None:
    server = start_server(sparql_timeout_s=1.0)
    answer = server.client.get("/sparql", params={"query": SLOW})
    assert answer.status_code == 503
    assert "time limit of 1 s" in answer.json()["detail"]
    # the killed worker was replaced: the endpoint still answers
    assert server.client.get("/sparql", params={"query": SPHERE_LABEL}).status_code == 200


def test_a_result_over_the_size_limit_is_refused(start_server: Callable[..., LiveServer]) -> None:
    server = start_server(sparql_max_result_bytes=2000)
    answer = server.client.get("/sparql", params={"query": "SELECT * WHERE { ?s ?p ?o }"})
    assert answer.status_code == 400
    assert "larger than the limit of 2000 bytes" in answer.json()["detail"]


@pytest.mark.parametrize("format", ["rdfxml", "turtle"])
def test_export_is_one_owl_ontology(live_server: LiveServer, format: str) -> None:
    answer = live_server.client.get("/export", params={"format": format})
    assert answer.status_code == 200
    graph = rdflib.Graph().parse(
        data=answer.content, format="xml" if format == "rdfxml" else "turtle"
    )
    ontologies = list(graph.subjects(rdflib.RDF.type, rdflib.OWL.Ontology))
    assert len(ontologies) == 1
    assert (rdflib.URIRef(SPHERE.value), rdflib.RDF.type, rdflib.OWL.Class) in graph


def test_export_rejects_an_unknown_graph(live_server: LiveServer) -> None:
    answer = live_server.client.get("/export", params={"graphs": "nonsense"})
    assert answer.status_code == 422
    assert "nonsense" in answer.text


def test_writes_need_the_token_when_one_is_set(start_server: Callable[..., LiveServer]) -> None:
    server = start_server(token="s3cret")
    assert server.client.post("/backup").status_code == 401
    wrong = server.client.post("/backup", headers={"Authorization": "Bearer nope"})
    assert wrong.status_code == 401
    right = server.client.post("/backup", headers={"Authorization": "Bearer s3cret"})
    assert right.status_code == 201
    named = right.json()["backup"]
    assert not Path(named).is_absolute()  # no server path in an answer
    assert (server.settings.data_dir / named).is_dir()
    # reads stay open
    assert server.client.get("/sparql", params={"query": SPHERE_LABEL}).status_code == 200
