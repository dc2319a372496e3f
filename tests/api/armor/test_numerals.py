"""ARMOR numerals are read as Java reads them, and a scene's primitives must be physical.

Python's ``float`` and ``int`` accept ``nan``, ``inf``, ``1_000``, surrounding spaces and other
scripts' digits; Java's ``Double.parseDouble`` and ``Integer.parseInt`` do not, and a
measurement must be finite. Runs the engine in this process over an in-memory store.
"""

import functools

import pytest

from api.armor import ArmorEngine
from api.protocol import ArmorDirectiveReq, ArmorDirectiveRes
from kg import Store, ensure_ontology
from reasoners.memory import SceneMemory
from tests.api.armor.conftest import request

_directive = functools.partial(request, ref="engram", client="camera")


@pytest.fixture
def engine() -> ArmorEngine:
    store = Store()
    ensure_ontology(store)
    return ArmorEngine(store, scene_memory=SceneMemory(store))


def _scene(ball: dict[str, str], table_axis: tuple[str, str, str]) -> list[ArmorDirectiveReq]:
    directives = [
        _directive("LOAD", "INIT", "", []),
        _directive("ADD", "IND", "CLASS", ["ball", "Sphere"]),
        _directive("ADD", "IND", "CLASS", ["table", "Plane"]),
    ]
    for prop, value in ball.items():
        directives.append(_directive("ADD", "DATAPROP", "IND", [prop, "ball", "DOUBLE", value]))
    table = {"centreX": "0.3", "centreY": "0.1", "centreZ": "0.1"}
    table |= dict(zip(("axisX", "axisY", "axisZ"), table_axis, strict=True))
    for prop, value in table.items():
        directives.append(_directive("ADD", "DATAPROP", "IND", [prop, "table", "DOUBLE", value]))
    directives.append(_directive("SCENE", "UPDATED", "", []))
    return directives


BALL = {"centreX": "0.3", "centreY": "0.3", "centreZ": "0.3", "radius": "0.05"}
UP = ("0", "0", "1")


def _run(engine: ArmorEngine, directives: list[ArmorDirectiveReq]) -> list[ArmorDirectiveRes]:
    return engine.execute_list(directives).armor_responses


def _stored_scenes(engine: ArmorEngine) -> int:
    """Quads in the store: any write shows."""
    return len(list(engine.store.quads()))


@pytest.mark.parametrize(
    "numeral",
    [
        "nan",
        "NaN",
        "inf",
        "Infinity",
        "-Infinity",
        "1_000",
        "\u0661\u0662",
        "1e999",
        "0x",
        "",
        "1.2.3",
    ],
)
def test_a_double_numeral_java_would_refuse_answers_208_and_stores_nothing(
    engine: ArmorEngine, numeral: str
) -> None:
    before = _stored_scenes(engine)
    responses = _run(engine, _scene(BALL | {"radius": numeral}, UP))
    failed = [r for r in responses if not r.success]
    assert failed[0].exit_code == 208
    assert repr(numeral) in failed[0].error_description
    assert _stored_scenes(engine) == before


@pytest.mark.parametrize(
    "numeral", ["0.05", " 0.05 ", "5e-2", "0.05d", "0.05F", ".05", "0x1.999999999999ap-5"]
)
def test_a_double_numeral_java_reads_is_accepted(engine: ArmorEngine, numeral: str) -> None:
    responses = _run(engine, _scene(BALL | {"radius": numeral}, UP))
    assert all(r.success for r in responses), [r.error_description for r in responses]


@pytest.mark.parametrize("numeral", ["1_000", " 12", "\u0661", "+", "1.0"])
def test_an_integer_numeral_java_would_refuse_answers_208(
    engine: ArmorEngine, numeral: str
) -> None:
    responses = _run(
        engine,
        [
            _directive("LOAD", "FILE", "", ["", "http://ex.org/r", "false", "PELLET", "true"]),
            _directive("ADD", "DATAPROP", "IND", ["count", "box", "INTEGER", numeral]),
        ],
    )
    assert responses[0].success
    assert (responses[1].success, responses[1].exit_code) == (False, 208)


@pytest.mark.parametrize(
    ("ball", "axis", "fragment"),
    [
        (BALL | {"radius": "-0.05"}, UP, "radius: got -0.05, expected a positive length"),
        (BALL | {"radius": "0"}, UP, "radius: got 0.0, expected a positive length"),
        (BALL, ("0", "0", "0"), "axis: got (0.0, 0.0, 0.0), expected a non-zero 3-vector"),
        (BALL | {"trackingId": "3.7"}, UP, "tracking_id: got 3.7, expected a non-negative integer"),
    ],
    ids=["negative-radius", "zero-radius", "zero-axis", "fractional-tracking-id"],
)
def test_a_primitive_that_is_not_physical_answers_212_and_stores_nothing(
    engine: ArmorEngine, ball: dict[str, str], axis: tuple[str, str, str], fragment: str
) -> None:
    before = _stored_scenes(engine)
    responses = _run(engine, _scene(ball, axis))
    assert (responses[-1].success, responses[-1].exit_code) == (False, 212)
    assert fragment in responses[-1].error_description
    assert _stored_scenes(engine) == before
