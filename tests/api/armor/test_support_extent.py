"""A support's extent travels from perception to the store: scene_primitives, the client's
directives (extentX/extentY), the engine's scene, the stored Plane."""

from pathlib import Path

import pytest

from api.armor import ArmorEngine
from api.client import primitive_directives
from api.perceive import scene_primitives
from api.protocol import ArmorDirectiveReq
from kg import Store
from kg.primitive import Primitive
from kg.scene_triples import read_primitive
from ontologies.vocab import EPISODIC, HAS_PRIMITIVE
from shapes import Primitive as Shape
from shapes import ShapeKind, StableScene


def test_a_supports_extent_is_in_the_scene_the_client_sends() -> None:
    ball = Shape(ShapeKind.SPHERE, centre=(0.1, 0.2, 0.05), radius=0.05, tracking_id=3)
    floor = Shape(
        ShapeKind.PLANE,
        centre=(0.0, 0.1, 0.0),
        axis=(0.0, 0.0, 1.0),
        hessian_offset=0.0,
        tracking_id=7,
        extent=(1.2, 0.8),
    )
    sent = scene_primitives(StableScene(0, None, (ball,), {}, 5, supports=(floor,)))
    assert [(p.id, p.extent_x, p.extent_y) for p in sent] == [
        ("sphere3", None, None),
        ("plane7", 1.2, 0.8),
    ]
    directives = primitive_directives(sent[1])
    assert ("ADD", "DATAPROP", "IND", ["extentX", "plane7", "DOUBLE", "1.2"]) in directives
    assert ("ADD", "DATAPROP", "IND", ["extentY", "plane7", "DOUBLE", "0.8"]) in directives


@pytest.mark.parametrize("side", [0.0, -1.0, float("nan")])
def test_the_client_refuses_an_extent_that_is_no_length(side: float) -> None:
    with pytest.raises(ValueError, match="extent_y: got"):
        Primitive("t", "Plane", centre=(0, 0, 0), axis=(0, 0, 1), extent_x=1.0, extent_y=side)


def test_the_engine_stores_the_extent_with_the_plane(tmp_path: Path) -> None:
    engine = ArmorEngine(Store(tmp_path / "store"))
    ball = Primitive("ball", "Sphere", centre=(0.3, 0.3, 0.3), radius=0.05)
    table = Primitive(
        "table",
        "Plane",
        centre=(0.3, 0.1, 0.1),
        axis=(0, 0, 1),
        hessian=-0.1,
        extent_x=1.5,
        extent_y=0.75,
    )
    directives = [
        ("LOAD", "FILE", "", ["", "http://ex.org/scenes", "false", "PELLET", "true"]),
        ("LOAD", "INIT", "", []),
        *primitive_directives(ball),
        *primitive_directives(table),
        ("SCENE", "UPDATED", "", []),
    ]
    result = engine.execute_list(
        [
            ArmorDirectiveReq(
                client_name="cam",
                reference_name="scenes",
                command=command,
                primary_command_spec=first,
                secondary_command_spec=second,
                args=args,
            )
            for command, first, second, args in directives
        ]
    )
    assert result.success, result
    store = engine.store
    read = [
        read_primitive(store, q.object, EPISODIC)  # type: ignore[arg-type]
        for q in store.quads(None, HAS_PRIMITIVE, None, EPISODIC)
    ]
    planes = [p for p in read if p is not None and p.kind == "Plane"]
    assert [(p.extent_x, p.extent_y) for p in planes] == [(1.5, 0.75)]
