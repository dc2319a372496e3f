"""The oracle: what Engram recognises equals what HermiT infers from Engram's own export.

Random scenes (seeded) are stored. The ontology given to HermiT is Engram's
export of the T-Box and the learned classes (``kg.export_triples``) plus one individual per
experienced scene: typed ``ExperiencedScene`` only (not with the class Engram stored it as), with
its signature links (derived here from the primary relations stored in the ``episodic`` graph
and the T-Box's signature-property annotations, independently of the encoder), its objects
typed with their leaf classes, and an ``owl:AllDifferent`` over those objects. The primitives'
own relation assertions are left out: they are transitive and inverse properties, which only
slow HermiT down and cannot change what a scene individual is. HermiT must then type every scene
with exactly the classes Engram recognises.
"""

import os
import random
import shutil
from pathlib import Path

import pytest
from pyoxigraph import BlankNode, NamedNode, RdfFormat, Triple, serialize

from kg import export_triples
from ontologies.vocab import (
    EPISODIC,
    EXPERIENCED_SCENE,
    HAS_PRIMITIVE,
    OWL_NS,
    PREFIXES,
    PRIMITIVE_LEAF_TYPES,
    RDF_FIRST,
    RDF_NIL,
    RDF_REST,
    RDF_TYPE,
    SIGNATURE_RELATION,
    SIGNATURE_SUBJECT_TYPE,
    SPATIAL_INVERSES,
    TBOX,
)
from reasoners.memory import SceneMemory

from .conftest import FakeClock, random_scene

SCENES = 20
"""HermiT needs ~12 s for 20 scenes (20 classes) but minutes for 30 with this generator, so the
oracle runs at 20; ``ENGRAM_ORACLE_SCENES`` raises it. The cost is not the ``AllDifferent``
axioms (one per scene, over that scene's objects) nor the individuals: at 30 scenes HermiT's
classification of the T-Box and the 30 learned classes alone, without any individual, takes
over 60 s (1.7 s at 20), as does its consistency check of the scenes without classification.
The qualified-cardinality equivalences themselves make the tableau expensive, so splitting the
scenes over several runs would not help."""
OWL_ALL_DIFFERENT = NamedNode(OWL_NS + "AllDifferent")
OWL_DISTINCT_MEMBERS = NamedNode(OWL_NS + "distinctMembers")


def scene_axioms(memory: SceneMemory) -> list[Triple]:
    """Signature links and AllDifferent for every experienced scene, from the stored triples."""
    store = memory.store
    prop: dict[tuple[NamedNode, NamedNode], NamedNode] = {}
    for quad in store.quads(None, SIGNATURE_SUBJECT_TYPE, None, TBOX):
        [relation] = [q.object for q in store.quads(quad.subject, SIGNATURE_RELATION, None, TBOX)]
        prop[(quad.object, relation)] = quad.subject  # type: ignore[index]
    out: list[Triple] = []
    for item in memory.items():
        out.append(Triple(item, RDF_TYPE, EXPERIENCED_SCENE))
        objects = [q.object for q in store.quads(item, HAS_PRIMITIVE, None, EPISODIC)]
        leaf = {
            o: next(
                q.object
                for q in store.quads(o, RDF_TYPE, None, EPISODIC)
                if q.object in PRIMITIVE_LEAF_TYPES
            )
            for o in objects
        }
        out += [Triple(o, RDF_TYPE, t) for o, t in leaf.items()]
        for s in objects:
            for quad in store.quads(s, None, None, EPISODIC):
                if quad.predicate in SPATIAL_INVERSES and quad.object in leaf:
                    o, relation = quad.object, quad.predicate
                    out.append(Triple(item, prop[(leaf[s], relation)], o))
                    out.append(Triple(item, prop[(leaf[o], SPATIAL_INVERSES[relation])], s))
        if len(objects) > 1:
            head: NamedNode | BlankNode = RDF_NIL
            for o in reversed(objects):
                cell = BlankNode()
                out += [Triple(cell, RDF_FIRST, o), Triple(cell, RDF_REST, head)]
                head = cell
            axiom = BlankNode()
            out += [
                Triple(axiom, RDF_TYPE, OWL_ALL_DIFFERENT),
                Triple(axiom, OWL_DISTINCT_MEMBERS, head),
            ]
    return out


@pytest.mark.slow
@pytest.mark.skipif(
    shutil.which("java") is None, reason="HermiT needs Java; scripts/test installs it"
)
def test_engram_recognises_exactly_what_hermit_infers(tmp_path: Path) -> None:
    owlready2 = pytest.importorskip("owlready2")
    from kg import Store

    clock = FakeClock()
    memory = SceneMemory(Store(), clock=clock)
    rng = random.Random(20250301)
    scenes = {}
    count = int(os.environ.get("ENGRAM_ORACLE_SCENES", SCENES))
    while len(scenes) < count:
        scene = random_scene(rng, 2, 4)
        if memory.encoder.signature(scene).complexity:
            scenes[memory.store_scene(scene).scene_item] = scene
        clock.advance(minutes=1)
    classes = {c.iri for c in memory.classes()}
    assert 5 < len(classes) <= count
    assert any(c.parents for c in memory.classes())  # there is a hierarchy to get right

    asserted_class = {Triple(item, RDF_TYPE, cls) for item in scenes for cls in classes}
    triples = [
        t
        for t in export_triples(memory.store, ["tbox", "memory", "episodic"])
        if t not in asserted_class
    ] + scene_axioms(memory)
    path = tmp_path / "oracle.owl"
    path.write_bytes(serialize(triples, format=RdfFormat.RDF_XML, prefixes=PREFIXES))

    world = owlready2.World()
    onto = world.get_ontology(path.as_uri()).load()
    with onto:
        owlready2.sync_reasoner_hermit(world, infer_property_values=False, debug=0)
    learned = {iri.value for iri in classes}
    mismatches = {}
    for item, scene in scenes.items():
        individual = world[item.value]
        hermit = {c.iri for c in individual.INDIRECT_is_a if getattr(c, "iri", None) in learned}
        engram_says = {r.cls.value for r in memory.recognise(scene)}
        if hermit != engram_says:
            mismatches[item.value] = (sorted(engram_says), sorted(hermit))
    assert mismatches == {}
