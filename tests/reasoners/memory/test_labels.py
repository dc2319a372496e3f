"""A learned class's label says what it holds; its short name is its skos:notation."""

from pyoxigraph import Literal

from kg import export_triples
from ontologies.vocab import MEMORY, OWL_ANNOTATION_PROPERTY, RDF_TYPE, RDFS_LABEL, SKOS_NOTATION
from reasoners.memory import SceneMemory

from .conftest import worked_example


def test_a_learned_class_is_labelled_by_its_definition(memory: SceneMemory) -> None:
    cls = memory.store_scene(worked_example()).stored_as
    [label] = [q.object for q in memory.store.quads(cls, RDFS_LABEL, None, MEMORY)]
    [notation] = [q.object for q in memory.store.quads(cls, SKOS_NOTATION, None, MEMORY)]
    assert notation == Literal("Scene-1")
    assert isinstance(label, Literal) and label.language == "en"
    phrases = label.value.split("; ")
    assert "sphere above a plane" in phrases and "plane below a sphere" in phrases
    assert len(phrases) == len(memory.reads.signature(cls))  # one phrase per restriction


def test_the_export_declares_the_notation_an_annotation_property(memory: SceneMemory) -> None:
    memory.store_scene(worked_example())
    triples = export_triples(memory.store, ["tbox", "memory"])
    kinds = {t.object for t in triples if t.subject == SKOS_NOTATION and t.predicate == RDF_TYPE}
    assert kinds == {OWL_ANNOTATION_PROPERTY}


def test_a_class_labelled_by_an_older_engram_is_relabelled_when_the_memory_opens(
    memory: SceneMemory,
) -> None:
    cls = memory.store_scene(worked_example()).stored_as
    store = memory.store
    with store.transaction() as tx:
        tx.delete_matching(cls, RDFS_LABEL, None, graph=MEMORY)
        tx.delete_matching(cls, SKOS_NOTATION, None, graph=MEMORY)
        tx.insert(cls, RDFS_LABEL, Literal("Scene-1"), MEMORY)
    SceneMemory(store)
    labels = [q.object.value for q in store.quads(cls, RDFS_LABEL, None, MEMORY)]
    assert len(labels) == 1 and "sphere above a plane" in labels[0]
    assert [q.object.value for q in store.quads(cls, SKOS_NOTATION, None, MEMORY)] == ["Scene-1"]
