"""A plane's extent (engram:extentX/Y): checked, stored with the Plane, read back, exported."""

import re

import pytest
import rdflib
from hypothesis import given, settings
from hypothesis import strategies as st

from kg import Store
from kg.errors import InvalidPrimitiveError
from kg.export import export
from kg.primitive import Primitive
from kg.scene_triples import read_primitive
from ontologies.vocab import EPISODIC, EXTENT, HAS_PRIMITIVE
from reasoners.memory import SceneMemory

from .conftest import FakeClock, sphere

ENGRAM = rdflib.Namespace("https://w3id.org/engram/ontology#")


def table(extent_x: float | None = 1.2, extent_y: float | None = 0.8) -> Primitive:
    return Primitive(
        "table",
        "Plane",
        centre=(0.3, 0.1, 0.0),
        axis=(0, 0, 1),
        hessian=0.0,
        extent_x=extent_x,
        extent_y=extent_y,
    )


@pytest.mark.parametrize(
    ("changes", "fragment"),
    [
        ({"extent_x": 0.0}, "extent_x: got 0.0, expected a positive length in metres"),
        ({"extent_y": -1}, "extent_y: got -1, expected a positive length in metres"),
        ({"extent_x": float("inf")}, "extent_x: got inf, expected a finite number"),
        ({"extent_y": "1"}, "extent_y: got '1', expected a finite number"),
    ],
)
def test_a_bad_extent_is_named(changes: dict, fragment: str) -> None:
    with pytest.raises(InvalidPrimitiveError, match=re.escape(fragment)):
        table(**{"extent_x": 1.2, "extent_y": 0.8, **changes})


def test_only_a_plane_has_an_extent() -> None:
    with pytest.raises(InvalidPrimitiveError, match=re.escape("extent_x: got 0.2, expected None")):
        Primitive("s", "Sphere", centre=(0, 0, 0), radius=0.1, extent_x=0.2)


def _stored(memory: SceneMemory, plane: Primitive) -> Primitive | None:
    item = memory.store_scene([sphere("ball", 0.3, 0.1, 0.05), plane]).scene_item
    [iri] = [
        q.object
        for q in memory.store.quads(item, HAS_PRIMITIVE, None, EPISODIC)
        if q.object.value.endswith("-1")  # the plane, the scene's second primitive
    ]
    return read_primitive(memory.store, iri, EPISODIC)  # type: ignore[arg-type]


sides = st.floats(min_value=1e-3, max_value=100.0, allow_nan=False, allow_infinity=False)


@settings(max_examples=15, deadline=None)
@given(extent_x=sides, extent_y=sides)
def test_the_extent_is_stored_with_the_plane_and_read_back(
    extent_x: float, extent_y: float
) -> None:
    memory = SceneMemory(Store(), clock=FakeClock())
    assert _stored(memory, table(extent_x, extent_y)) == table(extent_x, extent_y)


def test_a_plane_without_an_extent_is_read_back_without_one() -> None:
    memory = SceneMemory(Store(), clock=FakeClock())
    read = _stored(memory, table(None, None))
    assert read is not None and read.extent_x is None and read.extent_y is None


def test_the_owl_export_declares_the_extent_and_holds_the_tables() -> None:
    memory = SceneMemory(Store(), clock=FakeClock())
    _stored(memory, table(1.2, 0.8))
    graph = rdflib.Graph()
    graph.parse(data=export(memory.store, ["tbox", "episodic"]), format="xml")
    for prop, side in zip(EXTENT, (1.2, 0.8), strict=True):
        term = rdflib.URIRef(prop.value)
        assert (term, rdflib.RDF.type, rdflib.OWL.DatatypeProperty) in graph
        assert (term, rdflib.RDFS.domain, ENGRAM.Plane) in graph
        assert (term, rdflib.RDFS.range, rdflib.XSD.double) in graph
        [(plane, value)] = graph.subject_objects(term)
        assert (plane, rdflib.RDF.type, ENGRAM.Plane) in graph
        assert value.toPython() == side
