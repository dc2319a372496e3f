"""HermiT opens the export of a memory after a sleep pass forgot classes (the trash graph).

A forgotten class is written ``C rdfs:subClassOf engram:Trash`` and its experienced scenes move
to ``trash`` still typed ``engram:ExperiencedScene`` and ``C`` (and with ``engram:hasPrimitive``,
whose domain is ``ExperiencedScene``). The T-Box once made ``engram:Scene`` and ``engram:Trash``
disjoint, which made every forgotten scene both, the export inconsistent and HermiT (through
owlready2 or Protégé) refuse it; Trash is now a status, disjoint only with GeometricPrimitive
and MemoryPolicy.
"""

import datetime as dt
import re
import shutil
from pathlib import Path

import pytest
from pyoxigraph import Literal

from kg import Store
from kg.export import export, export_triples
from ontologies.vocab import GRAPHS, XSD_DATETIME
from reasoners.memory import SceneMemory

from .conftest import FakeClock
from .test_forgetting import BIG, SMALL

pytestmark = [
    pytest.mark.slow,
    pytest.mark.skipif(
        shutil.which("java") is None, reason="HermiT needs Java; scripts/test installs it"
    ),
]


@pytest.fixture
def slept(memory: SceneMemory, clock: FakeClock) -> SceneMemory:
    """A memory whose sleep passes forgot the class of a scene seen once, with that scene."""
    pytest.importorskip("owlready2")
    for _ in range(30):
        memory.store_scene(BIG)
    for _ in range(5):
        memory.retrieve(BIG)
    memory.store_scene(SMALL)
    clock.advance(seconds=memory.policy.forgetGracePeriodSeconds + 1)
    forgotten = [
        cls
        for _ in range(memory.policy.weakPassesToForget)
        for cls in memory.sleep().forgotten_classes
    ]
    assert forgotten and set(forgotten) <= set(memory.reads.trash())
    assert len(memory.reads.trash()) > len(forgotten)  # the forgotten scene went with its class
    return memory


def consistent(memory: SceneMemory, graphs: list[str], path: Path) -> bool:
    from .hermit_cli import is_consistent

    path.write_bytes(export(memory.store, graphs, "rdfxml"))
    return is_consistent(path, timeout=300)


def test_the_export_without_the_trash_is_consistent(slept: SceneMemory, tmp_path: Path) -> None:
    assert consistent(slept, ["tbox", "memory", "episodic"], tmp_path / "live.owl")


def test_the_export_with_the_trash_is_consistent(slept: SceneMemory, tmp_path: Path) -> None:
    assert consistent(slept, list(GRAPHS), tmp_path / "all.owl")


def test_an_export_after_sleep_passes_with_a_real_clock_is_accepted(tmp_path: Path) -> None:
    """A real clock has microseconds; HermiT refuses an xsd:dateTime with more than three
    fractional digits, so the memory keeps its times at milliseconds."""
    pytest.importorskip("owlready2")
    clock = FakeClock(dt.datetime(2026, 11, 23, 22, 6, 3, 8925, tzinfo=dt.UTC))
    memory = SceneMemory(Store(), clock=clock)
    memory.store_scene(BIG)
    clock.advance(microseconds=1234)
    memory.store_scene(SMALL)
    for _ in range(2):
        clock.advance(seconds=1.000321)
        memory.sleep()
    times = [
        t.object.value
        for t in export_triples(memory.store, list(GRAPHS))
        if isinstance(t.object, Literal) and t.object.datatype == XSD_DATETIME
    ]
    assert len(times) > 3 and not [t for t in times if re.search(r"\.\d{4}", t)], times
    assert consistent(memory, list(GRAPHS), tmp_path / "slept.owl")


def test_hermit_realises_each_exported_scene_into_its_stored_class(tmp_path: Path) -> None:
    """The oracle: the export's experienced scenes, their stored class types removed, are
    classified by HermiT from their links and AllDifferent alone."""
    pytest.importorskip("owlready2")
    from pyoxigraph import RdfFormat, serialize

    from ontologies.vocab import PREFIXES, RDF_TYPE

    from .conftest import worked_example
    from .hermit_cli import types

    memory = SceneMemory(Store(), clock=FakeClock())
    results = [memory.store_scene(scene) for scene in (worked_example(), BIG, SMALL, BIG)]
    stored = {r.scene_item: r.stored_as for r in results}
    classes = {c.iri for c in memory.reads.classes()}
    triples = [
        t
        for t in export_triples(memory.store, ["tbox", "memory", "episodic"])
        if not (t.predicate == RDF_TYPE and t.object in classes)
    ]
    path = tmp_path / "scenes.owl"
    path.write_bytes(serialize(triples, format=RdfFormat.RDF_XML, prefixes=PREFIXES))
    realised = types(path, timeout=300)
    for scene, cls in stored.items():
        assert cls.value in realised.get(scene.value, set()), (scene, realised.get(scene.value))
