"""PendingWrites.replace: the bulk form of delete() then insert(), for quads built by the
caller (the score view's terms)."""

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from pyoxigraph import BlankNode, DefaultGraph, Literal, Quad

from kg import Store
from ontologies.vocab import MEMORY, engram
from reasoners.batch import PendingWrites

QUADS = [Quad(engram(f"s{s}"), engram("p"), Literal(v), MEMORY) for s in range(3) for v in range(3)]
quad_lists = st.lists(st.sampled_from(QUADS), max_size=4)
steps = st.lists(
    st.one_of(
        st.tuples(st.just("insert"), quad_lists, st.just([])),
        st.tuples(st.just("delete"), quad_lists, st.just([])),
        st.tuples(st.just("replace"), quad_lists, quad_lists),
    ),
    max_size=8,
)


def committed(writes: PendingWrites, base: list[Quad]) -> set[Quad]:
    store = Store()
    with store.transaction() as tx:
        for quad in base:
            tx.insert(quad.subject, quad.predicate, quad.object, MEMORY)  # type: ignore[arg-type]
    with store.transaction() as tx:
        writes.copy_into(tx)
    return set(store.quads(None, None, None, MEMORY))


@settings(max_examples=60, deadline=None, derandomize=True)
@given(base=quad_lists, ops=steps)
def test_replace_is_deleting_then_inserting_one_by_one(base: list[Quad], ops: list) -> None:
    bulk, one_by_one = PendingWrites(), PendingWrites()
    for kind, first, second in ops:
        deletes, inserts = (first, second) if kind != "insert" else ([], first)
        if kind == "replace":
            bulk.replace(deletes, inserts)
        else:
            for quad in deletes:
                bulk.delete(quad.subject, quad.predicate, quad.object, MEMORY)  # type: ignore[arg-type]
            for quad in inserts:
                bulk.insert(quad.subject, quad.predicate, quad.object, MEMORY)  # type: ignore[arg-type]
        for quad in deletes:
            one_by_one.delete(quad.subject, quad.predicate, quad.object, MEMORY)  # type: ignore[arg-type]
        for quad in inserts:
            one_by_one.insert(quad.subject, quad.predicate, quad.object, MEMORY)  # type: ignore[arg-type]
    store = Store()
    assert set(bulk.quads(store)) == set(one_by_one.quads(store))
    assert committed(bulk, base) == committed(one_by_one, base)


@pytest.mark.parametrize(
    "quad",
    [
        Quad(engram("s"), engram("p"), Literal(1), DefaultGraph()),
        Quad(BlankNode(), engram("p"), Literal(1), MEMORY),
        Quad(engram("s"), engram("p"), BlankNode(), MEMORY),
    ],
)
def test_replace_refuses_a_quad_it_cannot_commit_as_it_is(quad: Quad) -> None:
    writes = PendingWrites()
    fine = Quad(engram("s"), engram("p"), Literal(2), MEMORY)
    with pytest.raises(TypeError, match="expected a quad in a named graph"):
        writes.replace([fine], [quad])
    assert writes.is_empty
