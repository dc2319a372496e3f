"""A memory damaged by hand: start-up and ``engram check`` name the node and the repair, and
``--fix`` mends a restriction exactly from its IRI."""

from pathlib import Path

import pytest
from pyoxigraph import Literal, NamedNode, Quad
from typer.testing import CliRunner

from api.cli import app
from kg import Store, ensure_ontology
from kg.primitive import Primitive
from ontologies.vocab import MEMORY, OWL_MIN_QUALIFIED_CARDINALITY, OWL_ON_CLASS, SCORE
from reasoners.check import DamagedMemoryError, check_memory, fix_memory, open_scene_memory
from reasoners.memory import SceneMemory

SCENE = [
    Primitive("ball", "Sphere", centre=(0.3, 0.3, 0.3), radius=0.05),
    Primitive("box", "Sphere", centre=(0.6, 0.3, 0.3), radius=0.05),
    Primitive("table", "Plane", centre=(0.3, 0.1, 0.1), axis=(0, 0, 1)),
]


def _learned(store: Store) -> Store:
    ensure_ontology(store)
    SceneMemory(store).store_scene(SCENE)
    return store


def _remove(store: Store, predicate: NamedNode) -> Quad:
    quad = next(iter(store.quads(None, predicate, None, MEMORY)))
    with store.transaction() as tx:
        tx.deletes.append(quad)
    return quad


@pytest.mark.parametrize(
    "damage",
    [
        lambda s: _remove(s, OWL_MIN_QUALIFIED_CARDINALITY),
        lambda s: _remove(s, OWL_ON_CLASS),
        lambda s: _replace_cardinality(s, Literal("many")),
    ],
    ids=["no-cardinality", "no-class", "bad-cardinality"],
)
def test_a_damaged_restriction_is_named_and_fixed(damage) -> None:  # type: ignore[no-untyped-def]
    store = _learned(Store())
    node = damage(store).subject.value
    with pytest.raises(DamagedMemoryError) as raised:
        open_scene_memory(store)
    assert node in str(raised.value)
    assert "engram check --fix" in str(raised.value)
    damages = check_memory(store)
    assert [d.node for d in damages] == [node]
    assert fix_memory(store, damages) == 1
    assert check_memory(store) == []
    assert len(open_scene_memory(store).recognise(SCENE)) >= 1


def _replace_cardinality(store: Store, value: Literal) -> Quad:
    quad = _remove(store, OWL_MIN_QUALIFIED_CARDINALITY)
    with store.transaction() as tx:
        tx.insert(quad.subject, quad.predicate, value, MEMORY)  # type: ignore[arg-type]
    return quad


def test_damage_that_cannot_be_mended_says_how_to_repair() -> None:
    store = _learned(Store())
    quad = _remove(store, SCORE)
    [damage] = check_memory(store)
    assert damage.node == quad.subject.value
    assert f"no {SCORE.value}" in damage.problem
    assert "backup" in damage.repair
    assert not damage.fixable


def test_a_sound_memory_has_nothing_to_report() -> None:
    assert check_memory(_learned(Store())) == []


@pytest.mark.slow
def test_engram_check_and_serve_name_the_damage(tmp_path: Path) -> None:
    store = _learned(Store(tmp_path / "store"))
    node = _remove(store, OWL_MIN_QUALIFIED_CARDINALITY).subject.value
    del store
    runner = CliRunner()
    checked = runner.invoke(app, ["check", "--data", str(tmp_path)])
    assert checked.exit_code == 1
    assert node in checked.output
    served = runner.invoke(app, ["serve", "--data", str(tmp_path), "--port", "1"])
    assert served.exit_code == 1
    assert node in served.output
    assert "Traceback" not in served.output
    fixed = runner.invoke(app, ["check", "--data", str(tmp_path), "--fix"])
    assert fixed.exit_code == 0
    assert "repaired 1 problem(s)" in fixed.output
    assert "sound" in runner.invoke(app, ["check", "--data", str(tmp_path)]).output
