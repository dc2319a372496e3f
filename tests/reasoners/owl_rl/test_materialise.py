"""materialise(): reasoner names, argument checks, and atomicity of the write."""

import importlib

import pytest
from pyoxigraph import NamedNode, RdfFormat

from kg import Store
from kg.transaction import Transaction
from reasoners.owl_rl import UnknownReasonerError, is_consistent, materialise
from reasoners.owl_rl.synthetic import scene_ontology

from .conftest import ASSERTED, INFERRED, Loader, graph_triples, recomputed

SCENE = "\n".join(scene_ontology(600, seed=5)).encode()


@pytest.mark.parametrize(
    "name", ["PELLET", "pellet", "HERMIT", "hermit", "FACT", "fact", "SNOROCKET", "OWL2RL", ""]
)
def test_armor_reasoner_names_are_aliases_of_one_engine(load: Loader, name: str) -> None:
    store = load(SCENE, RdfFormat.N_TRIPLES)
    report = materialise(store, asserted=ASSERTED, inferred=INFERRED, reasoner=name)
    assert report.added == report.inferred_total > 0


@pytest.mark.parametrize(
    ("kwargs", "error", "message"),
    [
        ({"reasoner": "ELK"}, UnknownReasonerError, "reasoner: got 'ELK', expected one of"),
        ({"reasoner": None}, UnknownReasonerError, "reasoner: got None"),
        ({"asserted": "ref"}, TypeError, "asserted: got 'ref', expected a NamedNode"),
        ({"inferred": ASSERTED}, ValueError, "expected a graph other than asserted"),
    ],
)
def test_bad_arguments_are_named_and_change_nothing(
    load: Loader, kwargs: dict[str, object], error: type[Exception], message: str
) -> None:
    store = load(SCENE, RdfFormat.N_TRIPLES)
    arguments: dict[str, object] = {"asserted": ASSERTED, "inferred": INFERRED, **kwargs}
    with pytest.raises(error, match=message):
        materialise(store, **arguments)  # type: ignore[arg-type]
    assert graph_triples(store) == set()


def _fail_on(monkeypatch: pytest.MonkeyPatch, method: str) -> None:
    original = getattr(Transaction, method)

    def failing(self: Transaction, *args: object, **kwargs: object) -> object:
        original(self, *args, **kwargs)  # the change is recorded, then the write fails
        raise OSError("disk full")

    monkeypatch.setattr(Transaction, method, failing)


def test_a_failure_during_a_full_reason_leaves_the_inferred_graph_as_it_was(
    load: Loader, monkeypatch: pytest.MonkeyPatch
) -> None:
    store = load(SCENE, RdfFormat.N_TRIPLES)
    materialise(store, asserted=ASSERTED, inferred=INFERRED)
    before = graph_triples(store)
    with store.transaction() as tx:  # a retraction: the next REASON recomputes everything
        tx.delete_matching(
            None, NamedNode("http://example.org/scene#inScene"), None, graph=ASSERTED
        )
    _fail_on(monkeypatch, "delete")
    with pytest.raises(OSError, match="disk full"):
        materialise(store, asserted=ASSERTED, inferred=INFERRED)
    assert graph_triples(store) == before
    monkeypatch.undo()
    report = materialise(store, asserted=ASSERTED, inferred=INFERRED)
    assert not report.incremental and report.removed > 0
    assert graph_triples(store) == recomputed(store)


def test_a_failure_during_an_incremental_reason_leaves_graph_and_state_consistent(
    load: Loader, monkeypatch: pytest.MonkeyPatch
) -> None:
    store = load(SCENE, RdfFormat.N_TRIPLES)
    materialise(store, asserted=ASSERTED, inferred=INFERRED)
    before = graph_triples(store)
    cube, obj = NamedNode("http://example.org/scene#Cube"), NamedNode("http://example.org/new")
    with store.transaction() as tx:
        tx.insert(obj, NamedNode("http://www.w3.org/1999/02/22-rdf-syntax-ns#type"), cube, ASSERTED)
    module = importlib.import_module("reasoners.owl_rl.materialise")

    def failing_term(text: str) -> object:
        raise OSError("out of memory")  # while the transaction is being built

    monkeypatch.setattr(module, "to_term", failing_term)
    with pytest.raises(OSError):
        materialise(store, asserted=ASSERTED, inferred=INFERRED)
    assert graph_triples(store) == before
    monkeypatch.undo()
    report = materialise(store, asserted=ASSERTED, inferred=INFERRED)
    assert report.added > 0
    assert (
        f"<{obj.value}> <http://www.w3.org/1999/02/22-rdf-syntax-ns#type> <http://example.org/scene#Box>"
        in graph_triples(store)
    )


def test_is_consistent_without_a_reason_writes_nothing(load: Loader) -> None:
    store = load(SCENE, RdfFormat.N_TRIPLES)
    assert is_consistent(store, asserted=ASSERTED, inferred=INFERRED).consistent
    assert graph_triples(store) == set()


def test_reasoning_on_disk_survives_reopening(tmp_path: object) -> None:
    from pathlib import Path

    path = Path(str(tmp_path)) / "store"
    store = Store(path)
    with store.transaction() as tx:
        tx.load(SCENE, format=RdfFormat.N_TRIPLES, graph=ASSERTED)
    materialise(store, asserted=ASSERTED, inferred=INFERRED)
    expected = graph_triples(store)
    del store
    reopened = Store(path)
    assert graph_triples(reopened) == expected
    report = materialise(reopened, asserted=ASSERTED, inferred=INFERRED)  # new process: no state
    assert (report.incremental, report.added, report.removed) == (False, 0, 0)
