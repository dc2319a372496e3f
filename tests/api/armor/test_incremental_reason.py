"""REASON through the directive engine after a few changes: incremental, and equal to a full one.

The engine runs in-process on an on-disk store. Each test compares the inferred graph the
directives left with a full REASON of the same asserted graph by a fresh engine on a fresh store,
and spies on the reasoner's entry points to check which path (incremental or recomputation) ran.
"""

from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest

from api.armor import ArmorEngine, reasoning
from api.protocol import ArmorDirectiveReq, ArmorDirectiveRes
from kg import Store
from ontologies.vocab import ARMOR_REGISTRY, reference_graph
from reasoners.owl_rl import Prepared, ReasonReport
from reasoners.owl_rl.materialise import _slot
from reasoners.owl_rl.synthetic import EX, scene_ontology
from tests.api.armor.conftest import request

PREFIX = EX.rstrip("#")
TBOX = """\
@prefix : <http://ex.org/t#> .
@prefix owl: <http://www.w3.org/2002/07/owl#> .
@prefix rdfs: <http://www.w3.org/2000/01/rdf-schema#> .
<http://ex.org/t> a owl:Ontology .
:A a owl:Class ; rdfs:subClassOf :B .
:B a owl:Class .
:p a owl:ObjectProperty .
:D a owl:Class ;
   owl:equivalentClass [ a owl:Restriction ; owl:onProperty :p ; owl:someValuesFrom :B ] .
"""


def d(
    command: str, first: str = "", second: str = "", *args: str, ref: str = "r"
) -> ArmorDirectiveReq:
    return request(command, first, second, list(args), ref=ref)


class Spy:
    """Records what the reasoner did for each REASON of the directive layer."""

    def __init__(self, monkeypatch: pytest.MonkeyPatch) -> None:
        self.prepared: list[Prepared] = []
        self.reports: list[ReasonReport] = []
        prepare = getattr(reasoning, "prepare_delta")  # noqa: B009  (what reasoning.py calls)
        materialise = getattr(reasoning, "materialise")  # noqa: B009

        def spy_prepare(*args: Any, **kwargs: Any) -> Prepared:
            result: Prepared = prepare(*args, **kwargs)
            self.prepared.append(result)
            return result

        def spy_materialise(*args: Any, **kwargs: Any) -> ReasonReport:
            result: ReasonReport = materialise(*args, **kwargs)
            self.reports.append(result)
            return result

        monkeypatch.setattr(reasoning, "prepare_delta", spy_prepare)
        monkeypatch.setattr(reasoning, "materialise", spy_materialise)

    def clear(self) -> None:
        self.prepared, self.reports = [], []


@pytest.fixture
def spy(monkeypatch: pytest.MonkeyPatch) -> Spy:
    return Spy(monkeypatch)


@pytest.fixture
def engine(tmp_path: Path) -> Iterator[ArmorEngine]:
    yield ArmorEngine(Store(tmp_path / "store"))


def run(engine: ArmorEngine, *directives: ArmorDirectiveReq) -> list[ArmorDirectiveRes]:
    result = engine.execute_list(list(directives))
    assert result.success, result
    return result.armor_responses


def ntriples(store: Store, graph: Any) -> set[bytes]:
    return set(store.graph_ntriples(graph).splitlines())


def full_reason(engine: ArmorEngine, ref: str, tmp_path: Path) -> set[bytes]:
    """The inferred graph a fresh engine's full REASON gives for the same asserted graph."""
    fresh = Store(tmp_path / f"fresh-{len(list(tmp_path.iterdir()))}")
    with fresh.transaction() as tx:
        tx.inserts.extend(engine.store.quads(graph=reference_graph(ref)))
        tx.inserts.extend(engine.store.quads(graph=ARMOR_REGISTRY))
    run(ArmorEngine(fresh), d("REASON", ref=ref))
    return ntriples(fresh, reference_graph(ref, inferred=True))


def load(
    engine: ArmorEngine, tmp_path: Path, text: str, *, buffered_reasoner: bool, **kw: str
) -> None:
    name = kw.get("name", "onto.nt")
    path = tmp_path / name
    path.write_text(text)
    prefix = kw.get("prefix", PREFIX)
    run(engine, d("LOAD", "FILE", "", str(path), prefix, "false", "PELLET", str(buffered_reasoner)))


def scene(engine: ArmorEngine, tmp_path: Path, *, buffered_reasoner: bool) -> None:
    load(
        engine,
        tmp_path,
        "\n".join(scene_ontology(3_000, seed=1)) + "\n",
        buffered_reasoner=buffered_reasoner,
    )


def test_a_list_reasons_over_its_own_writes_incrementally(
    engine: ArmorEngine, spy: Spy, tmp_path: Path
) -> None:
    scene(engine, tmp_path, buffered_reasoner=False)
    inferred = reference_graph("r", inferred=True)
    spy.clear()
    responses = run(
        engine,
        d("ADD", "IND", "CLASS", "new_obj", "Mug"),
        d("ADD", "OBJECTPROP", "IND", "inScene", "new_obj", "scene3"),
        d("QUERY", "IND", "", "new_obj"),  # the list sees its writes' inferences
        d("ADD", "DATAPROP", "IND", "score", "new_obj", "DOUBLE", "0.50"),
        d("ADD", "OBJECTPROP", "IND", "above", "new_obj", "scene3_obj0"),
        d("ADD", "IND", "CLASS", "new_obj2", "Cube"),
        d("REASON"),
        d("QUERY", "IND", "CLASS", "StackedObject"),
    )
    assert {f"<{EX}{c}>" for c in ("Mug", "Container", "Graspable", "PhysicalObject")} <= set(
        responses[2].queried_objects
    )
    assert f"<{EX}new_obj>" in responses[-1].queried_objects
    assert spy.prepared and all(p.incremental and not p.replaces for p in spy.prepared)
    assert not spy.reports  # nothing re-read the reference
    assert ntriples(engine.store, inferred) == full_reason(engine, "r", tmp_path)
    # an unbuffered reasoner's automatic reasoning at the commit of a single ADD, too
    spy.clear()
    run(engine, d("ADD", "OBJECTPROP", "IND", "near", "new_obj2", "scene3_obj1"))
    assert [p.incremental for p in spy.prepared] == [True]
    assert ntriples(engine.store, inferred) == full_reason(engine, "r", tmp_path)


def test_buffered_reasoner_catches_up_incrementally_on_reason(
    engine: ArmorEngine, spy: Spy, tmp_path: Path
) -> None:
    scene(engine, tmp_path, buffered_reasoner=True)
    run(engine, d("REASON"))
    inferred = reference_graph("r", inferred=True)
    before = ntriples(engine.store, inferred)
    spy.clear()
    run(engine, d("ADD", "IND", "CLASS", "b1", "Bottle"))
    run(engine, d("ADD", "OBJECTPROP", "IND", "partOf", "b1", "scene5_obj0"))
    run(engine, d("ADD", "DATAPROP", "IND", "level", "b1", "INTEGER", "02"))
    assert not spy.prepared and not spy.reports
    assert ntriples(engine.store, inferred) == before  # stale until REASON, as in ARMOR
    run(engine, d("REASON"))
    assert [r.incremental for r in spy.reports] == [True]
    assert ntriples(engine.store, inferred) == full_reason(engine, "r", tmp_path)


def test_buffered_reasoner_re_derives_only_the_region_of_retractions_on_reason(
    engine: ArmorEngine, spy: Spy, tmp_path: Path
) -> None:
    """REMOVE directives committed without reasoning are handed to the reasoner (not dropped
    with its state): the next REASON re-derives the part of the closure they touch."""
    scene(engine, tmp_path, buffered_reasoner=True)
    run(engine, d("REASON"))
    inferred = reference_graph("r", inferred=True)
    spy.clear()
    run(engine, d("REMOVE", "OBJECTPROP", "IND", "inScene", "scene2_obj1", "scene2"))
    run(engine, d("REMOVE", "IND", "", "scene3_obj0"))
    run(
        engine,
        d("ADD", "IND", "CLASS", "b1", "Bottle"),
        d("REMOVE", "IND", "CLASS", "b1", "Bottle"),
    )
    assert not spy.prepared and not spy.reports
    run(engine, d("REASON"))
    assert [(r.scoped, r.incremental) for r in spy.reports] == [(True, False)]
    assert spy.reports[0].removed > 0
    assert ntriples(engine.store, inferred) == full_reason(engine, "r", tmp_path)
    spy.clear()
    run(engine, d("REASON"))  # nothing changed since
    assert [(r.added, r.removed, r.incremental) for r in spy.reports] == [(0, 0, True)]


def test_an_unbuffered_reasoner_re_derives_only_the_region_of_a_lists_retractions(
    engine: ArmorEngine, spy: Spy, tmp_path: Path
) -> None:
    """REMOVE directives in a list: the delta committed with them comes from their region of
    the closure (neither graph re-read), and the kept state serves the next list."""
    scene(engine, tmp_path, buffered_reasoner=False)
    inferred = reference_graph("r", inferred=True)
    spy.clear()
    reads: list[str] = []
    with engine.store.tracing(lambda kind, text, _: reads.append(text)):
        run(
            engine,
            d("REMOVE", "IND", "CLASS", "scene2_obj1", "Cone"),
            d("QUERY", "IND", "", "scene2_obj1"),
            d("REMOVE", "OBJECTPROP", "IND", "inScene", "scene3_obj0", "scene3"),
            d("ADD", "IND", "CLASS", "scene3_obj0", "Sphere"),
        )
    # the QUERY's reasoning re-derived a region; nothing replaced the list's delta
    assert not spy.prepared[0].incremental
    assert spy.prepared and not any(p.replaces for p in spy.prepared)
    assert not [text for text in reads if text.startswith("DUMP GRAPH")]
    assert ntriples(engine.store, inferred) == full_reason(engine, "r", tmp_path)
    spy.clear()
    run(engine, d("REMOVE", "IND", "", "scene4_obj2"))
    assert [p.replaces for p in spy.prepared] == [False]
    assert ntriples(engine.store, inferred) == full_reason(engine, "r", tmp_path)


def test_retractions_renames_and_reloads_in_a_list_equal_a_full_reason(
    engine: ArmorEngine, spy: Spy, tmp_path: Path
) -> None:
    scene(engine, tmp_path, buffered_reasoner=False)
    inferred = reference_graph("r", inferred=True)
    spy.clear()
    run(
        engine,
        d("ADD", "IND", "CLASS", "gone", "Mug"),
        d("QUERY", "IND", "", "gone"),
        d("REMOVE", "IND", "", "scene3_obj0"),
        d("RENAME", "IND", "", "scene4_obj1", "renamed"),
        d("QUERY", "IND", "", "renamed"),
        d("REMOVE", "IND", "CLASS", "gone", "Mug"),
    )
    assert any(p.replaces for p in spy.prepared)  # a retraction recomputes
    assert ntriples(engine.store, inferred) == full_reason(engine, "r", tmp_path)
    # DROP and LOAD again in one list: the reasoner starts from the new graph
    run(
        engine,
        d("DROP"),
        d("LOAD", "FILE", "", str(tmp_path / "onto.nt"), PREFIX, "false", "PELLET", "false"),
        d("ADD", "IND", "CLASS", "again", "Sphere"),
    )
    assert ntriples(engine.store, inferred) == full_reason(engine, "r", tmp_path)
    spy.clear()
    run(engine, d("ADD", "IND", "CLASS", "again2", "Cone"))
    assert [p.incremental for p in spy.prepared] == [True]
    assert ntriples(engine.store, inferred) == full_reason(engine, "r", tmp_path)


def test_a_failing_list_leaves_the_inferred_graph_and_the_reasoner_as_the_store(
    engine: ArmorEngine, spy: Spy, tmp_path: Path
) -> None:
    load(engine, tmp_path, TBOX, buffered_reasoner=False, name="t.ttl", prefix="http://ex.org/t")
    run(engine, d("ADD", "IND", "", "y"))
    asserted, inferred = reference_graph("r"), reference_graph("r", inferred=True)
    before = (ntriples(engine.store, asserted), ntriples(engine.store, inferred))
    result = engine.execute_list(
        [
            d("ADD", "IND", "CLASS", "x", "A"),
            d("QUERY", "IND", "", "x"),  # reasons over the pending write: x is a B
            d("ADD", "IND", "CLASS", "too-few-args"),  # 208: the list fails
        ]
    )
    assert not result.success
    assert set(result.armor_responses[1].queried_objects) == {
        "<http://ex.org/t#A>",
        "<http://ex.org/t#B>",
    }
    assert result.armor_responses[2].exit_code == 208
    assert (ntriples(engine.store, asserted), ntriples(engine.store, inferred)) == before
    assert _slot(engine.store, asserted, inferred).state is None  # the next REASON recomputes
    # had the reasoner kept "x is a B", y would now be a D
    spy.clear()
    responses = run(
        engine,
        d("ADD", "OBJECTPROP", "IND", "p", "y", "x"),
        d("QUERY", "IND", "CLASS", "D"),
    )
    assert responses[1].queried_objects == []
    assert [p.replaces for p in spy.prepared] == [True]
    assert ntriples(engine.store, inferred) == full_reason(engine, "r", tmp_path)
    # and from there on, incremental again
    spy.clear()
    responses = run(engine, d("ADD", "IND", "CLASS", "x", "A"), d("QUERY", "IND", "CLASS", "D"))
    assert responses[1].queried_objects == ["<http://ex.org/t#y>"]
    assert [p.incremental for p in spy.prepared] == [True]
    assert ntriples(engine.store, inferred) == full_reason(engine, "r", tmp_path)


def test_other_lists_do_not_see_a_lists_inferences_before_its_commit(
    engine: ArmorEngine, tmp_path: Path
) -> None:
    load(engine, tmp_path, TBOX, buffered_reasoner=False, name="t.ttl", prefix="http://ex.org/t")
    inferred = reference_graph("r", inferred=True)
    seen: list[list[str]] = []
    # another list's QUERY (it takes no lock), run while this list holds pending inferences
    original = engine._run

    def run_and_peek(session: Any, request: ArmorDirectiveReq, style: Any) -> ArmorDirectiveRes:
        response = original(session, request, style)
        if request.client_name == "tester" and request.command == "QUERY":
            other = d("QUERY", "IND", "CLASS", "B").model_copy(update={"client_name": "other"})
            seen.append(engine.execute(other).queried_objects)
        return response

    engine._run = run_and_peek  # type: ignore[method-assign]
    run(engine, d("ADD", "IND", "CLASS", "x", "A"), d("QUERY", "IND", "CLASS", "B"))
    engine._run = original  # type: ignore[method-assign]
    assert seen == [[]]
    assert engine.execute(d("QUERY", "IND", "CLASS", "B")).queried_objects == [
        "<http://ex.org/t#x>"
    ]
    assert (
        b"<http://ex.org/t#x> <http://www.w3.org/1999/02/22-rdf-syntax-ns#type> <http://ex.org/t#B>"
        in {line.rstrip(b" .") for line in ntriples(engine.store, inferred)}
    )
