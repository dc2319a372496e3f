"""A primitive written as triples reads back as the same primitive (kg.scene_triples)."""

import math

import pytest
from hypothesis import given
from hypothesis import strategies as st
from pyoxigraph import Literal, NamedNode, Quad

from kg import Store
from kg.primitive import KINDS, Primitive
from kg.scene_triples import read_primitive, read_scene, write_primitive
from ontologies.vocab import EPISODIC, HAS_PRIMITIVE, RADIUS, TRASH, engram

ITEM = engram("Scene-1-experience-1")
numbers = st.floats(-1e6, 1e6, allow_nan=False)
lengths = st.floats(1e-6, 1e6)
vectors = st.tuples(numbers, numbers, numbers)
axes = vectors.filter(lambda v: 1e-3 < math.hypot(*v) < 1e6)
colours = st.tuples(*[st.floats(0, 1)] * 3)


@st.composite
def primitives(draw: st.DrawFn) -> Primitive:
    kind = draw(st.sampled_from(KINDS))
    optional = st.none() | st.just(True)
    fields: dict[str, object] = {
        "colour": draw(st.none() | colours),
        "tracking_id": draw(st.none() | st.integers(0, 2**62)),
    }
    if kind != "Sphere":
        fields["axis"] = draw(axes)
    if kind != "Plane" and draw(optional):
        fields["radius"] = draw(lengths)
    if kind in ("Cylinder", "Cone") and draw(optional):
        fields["height"] = draw(lengths)
    extra = {"Cone": ("apex", vectors), "Cylinder": ("point_on_axis", vectors)}
    if kind in extra and draw(optional):
        name, values = extra[kind]
        fields[name] = draw(values)
    if kind == "Plane" and draw(optional):
        fields["hessian"] = draw(numbers)
    name = draw(st.text(min_size=1).filter(str.strip))
    return Primitive(name, kind, draw(vectors), **fields)  # type: ignore[arg-type]


def _stored(store: Store, scene: list[Primitive], graph: NamedNode = EPISODIC) -> None:
    with store.transaction() as tx:
        for k, primitive in enumerate(scene):
            member = NamedNode(f"{ITEM.value}-{k}")
            tx.insert(ITEM, HAS_PRIMITIVE, member, graph)
            write_primitive(tx, member, primitive, graph)


@given(primitives())
def test_a_written_primitive_reads_back_equal(primitive: Primitive) -> None:
    store = Store()
    _stored(store, [primitive])
    assert read_primitive(store, NamedNode(f"{ITEM.value}-0"), EPISODIC) == primitive


def test_a_scene_reads_back_in_the_order_it_was_written() -> None:
    scene = [
        Primitive(f"ball{k}", "Sphere", centre=(k / 10, 0.0, 0.0), radius=0.01) for k in range(12)
    ]
    store = Store()
    _stored(store, scene, TRASH)
    assert [p for _, p in read_scene(store, ITEM, TRASH)] == scene
    assert read_scene(store, ITEM, EPISODIC) == []


@pytest.mark.parametrize(
    "damage",
    [
        Quad(NamedNode(f"{ITEM.value}-0"), RADIUS, Literal(-1.0), EPISODIC),  # out of range
        Quad(NamedNode(f"{ITEM.value}-0"), engram("centreY"), Literal("y"), EPISODIC),  # no number
    ],
)
def test_a_primitive_stored_out_of_range_reads_as_none(damage: Quad) -> None:
    store = Store()
    ball = Primitive("ball", "Sphere", centre=(0.0, 0.0, 0.0), radius=0.1)
    member = NamedNode(f"{ITEM.value}-0")
    with store.transaction() as tx:
        write_primitive(tx, member, ball, EPISODIC)
    with store.transaction() as tx:
        tx.delete_matching(member, damage.predicate, graph=EPISODIC)
        tx.insert(member, damage.predicate, damage.object, EPISODIC)
    assert read_primitive(store, member, EPISODIC) is None
