"""What one update writes: the touched class and the new scene, not the whole branch; shared
restriction nodes are exported as separate blank nodes; derived scores survive a restart."""

from pathlib import Path

from pyoxigraph import BlankNode, Literal

from kg import Store, export_triples
from ontologies.vocab import MEMORY, OWL_ON_PROPERTY, RDFS_SUBCLASSOF, SCORE
from reasoners import persist
from reasoners.memory import SceneMemory

from .conftest import FakeClock, plane, sphere, worked_example

TWO_SPHERES = [
    sphere("s1", 0.29, 0.1, 0.3),
    sphere("s2", 0.31, 0.1, 0.3),
    plane("p", 0.3, 0.1, 0.1),
]


def memory_quads(memory: SceneMemory, subject: object) -> set[tuple[object, object]]:
    return {(q.predicate, q.object) for q in memory.store.quads(subject, None, None, MEMORY)}  # type: ignore[arg-type]


def test_learning_a_child_rewrites_only_the_score_view_of_its_ancestors(
    memory: SceneMemory,
) -> None:
    parent = memory.store_scene([sphere("s", 0.3, 0.1, 0.3), plane("p", 0.3, 0.1, 0.1)]).stored_as
    view = persist.VIEW_PREDICATES
    before = memory_quads(memory, parent)
    zeta_before = memory.reads.item_scores(parent).raw_score
    child = memory.store_scene(TWO_SPHERES)
    assert child.learned and child.parents == (parent,)
    after = memory_quads(memory, parent)
    assert {t for t in after if t[0] not in view} == {t for t in before if t[0] not in view}
    assert {t for t in after if t[0] in view} != {t for t in before if t[0] in view}
    assert memory.reads.item_scores(parent).raw_score != zeta_before  # the live ζ is derived now
    rows = memory.store.select("memory_class_scores")
    [raw] = [float(r["raw"].value) for r in rows if r["class"] == parent]  # type: ignore[union-attr]
    assert raw == memory.reads.item_scores(parent).raw_score  # the view gives it exactly
    quads = memory_quads(memory, parent)
    memory.sleep()  # the level and ζ are derived: a sleep pass rewrites neither
    assert memory_quads(memory, parent) == quads
    [stored] = [o for p, o in quads if p == SCORE]
    assert stored == Literal(zeta_before)  # the class's own last update's


def test_classes_share_restriction_nodes_and_the_export_unshares_them(
    memory: SceneMemory,
) -> None:
    memory.store_scene([sphere("s", 0.3, 0.1, 0.3), plane("p", 0.3, 0.1, 0.1)])
    memory.store_scene(TWO_SPHERES)
    signatures = [c.signature for c in memory.reads.classes()]
    distinct = {item for signature in signatures for item in signature.items()}
    assert len(distinct) < sum(len(s) for s in signatures)  # some restriction is shared
    shared = [
        q.subject
        for q in memory.store.quads(None, OWL_ON_PROPERTY, None, MEMORY)
        if persist.is_restriction(q.subject)
    ]
    assert len(shared) == len(set(shared)) == len(distinct)
    triples = export_triples(memory.store, ["tbox", "memory"])
    uses: dict[BlankNode, int] = {}
    for t in triples:
        if isinstance(t.object, BlankNode):
            uses[t.object] = uses.get(t.object, 0) + 1
    assert uses and max(uses.values()) == 1
    restrictions = [t for t in triples if t.predicate == OWL_ON_PROPERTY]
    assert len(restrictions) == sum(len(s) for s in signatures)  # one blank node per use


def test_forgetting_the_last_user_of_a_restriction_deletes_its_node(
    memory: SceneMemory, clock: FakeClock
) -> None:
    from .test_forgetting import set_policy

    memory.store_scene(worked_example())
    memory.store_scene(TWO_SPHERES)
    set_policy(
        memory.store,
        highLevelThreshold=0.995,
        weakLevelThreshold=0.99,
        weakPassesToForget=1,
        forgetGracePeriodSeconds=0.0,
    )
    memory = SceneMemory(memory.store, clock=clock)
    clock.advance(hours=1)
    report = memory.sleep()
    assert report.forgotten_classes
    used = {
        persist.restriction_iri(key, n)
        for c in memory.reads.classes()
        for key, n in c.signature.items()
    }
    stored = {
        q.subject
        for q in memory.store.quads(None, OWL_ON_PROPERTY, None, MEMORY)
        if persist.is_restriction(q.subject)
    }
    assert stored == used
    for cls in report.forgotten_classes:
        memory.restore(cls)
    assert SceneMemory(memory.store, clock=clock).reads.classes() == memory.reads.classes()


def test_a_reopened_memory_derives_the_same_scores_without_a_sleep_pass(
    tmp_path: Path, clock: FakeClock
) -> None:
    memory = SceneMemory(Store(tmp_path / "store"), clock=clock)
    for scene in (worked_example(), TWO_SPHERES, worked_example()):
        memory.store_scene(scene)
        clock.advance(minutes=5)
    memory.retrieve([("Sphere", "isAboveOf", "Plane")])
    classes, store = memory.reads.classes(), memory.store
    assert any(p == RDFS_SUBCLASSOF for c in classes for p, _ in memory_quads(memory, c.iri))
    del memory, store
    reopened = SceneMemory(Store(tmp_path / "store"), clock=clock)
    assert reopened.reads.classes() == classes
