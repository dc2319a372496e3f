"""Physical checks on primitive attributes where they enter: a memory directive refuses an
impossible value when it is sent, and the client's ScenePrimitive before sending it."""

from typing import Any

import pytest

from api.armor import ArmorEngine
from api.armor.models import ArmorDirectiveReq
from api.client import ScenePrimitive
from kg import Store, ensure_ontology
from reasoners.memory import SceneMemory

INVALID_ARGUMENTS, MEMORY_ERROR = 208, 212


@pytest.fixture
def engine() -> ArmorEngine:
    store = Store()
    ensure_ontology(store)
    return ArmorEngine(store, scene_memory=SceneMemory(store))


def _run(engine: ArmorEngine, command: str, first: str = "", second: str = "", *args: str) -> Any:
    return engine.execute(
        ArmorDirectiveReq(
            client_name="camera",
            reference_name="engram",
            command=command,
            primary_command_spec=first,
            secondary_command_spec=second,
            args=list(args),
        )
    )


def _value(engine: ArmorEngine, attribute: str, obj: str, value: str, kind: str = "DOUBLE") -> Any:
    return _run(engine, "ADD", "DATAPROP", "IND", attribute, obj, kind, value)


# (attribute, value, value type, message fragment)
IMPOSSIBLE = [
    ("radius", "-0.5", "DOUBLE", "positive length"),
    ("radius", "0", "DOUBLE", "positive length"),
    ("height", "-1e-3", "DOUBLE", "positive length"),
    ("colourG", "1.5", "DOUBLE", "[0, 1]"),
    ("colourR", "-0.1", "DOUBLE", "[0, 1]"),
    ("trackingId", "-3", "INTEGER", "whole number"),
    ("trackingId", "1.5", "DOUBLE", "whole number"),
    ("radius", "NaN", "DOUBLE", "finite"),
    ("centreX", "Infinity", "DOUBLE", "finite"),
]


@pytest.mark.parametrize(("attribute", "value", "kind", "fragment"), IMPOSSIBLE)
def test_an_impossible_attribute_is_refused_when_sent(
    engine: ArmorEngine, attribute: str, value: str, kind: str, fragment: str
) -> None:
    assert _run(engine, "LOAD", "INIT").success
    assert _run(engine, "ADD", "IND", "CLASS", "can", "Cylinder").success
    answer = _value(engine, attribute, "can", value, kind)
    assert (answer.success, answer.exit_code) == (False, INVALID_ARGUMENTS), answer
    assert fragment in answer.error_description and repr(value) in answer.error_description
    # the scene is unharmed: sent with possible values, it is stored
    for name, number in [("centreX", "0"), ("centreY", "0"), ("centreZ", "0.1")]:
        assert _value(engine, name, "can", number).success
    for name, number in [("axisX", "0"), ("axisY", "0"), ("axisZ", "1")]:
        assert _value(engine, name, "can", number).success
    assert _value(engine, "radius", "can", "0.04").success
    assert _value(engine, "height", "can", "0.14").success
    assert _run(engine, "ADD", "IND", "CLASS", "ball", "Sphere").success
    for name, number in [("centreX", "0.3"), ("centreY", "0"), ("centreZ", "0.04")]:
        assert _value(engine, name, "ball", number).success
    assert _value(engine, "radius", "ball", "0.04").success
    stored = _run(engine, "SCENE", "UPDATED")
    assert stored.success, stored.error_description


def test_a_zero_axis_is_refused_when_the_scene_is_stored(engine: ArmorEngine) -> None:
    assert _run(engine, "LOAD", "INIT").success
    assert _run(engine, "ADD", "IND", "CLASS", "table", "Plane").success
    for name in ("centreX", "centreY", "centreZ", "axisX", "axisY", "axisZ"):
        assert _value(engine, name, "table", "0").success
    answer = _run(engine, "SCENE", "UPDATED")
    assert (answer.success, answer.exit_code) == (False, MEMORY_ERROR)
    assert "axis" in answer.error_description


# (fields, message fragment)
CLIENT_IMPOSSIBLE: list[tuple[dict[str, Any], str]] = [
    ({"kind": "Sphere", "radius": -0.05}, "radius"),
    ({"kind": "Cylinder", "axis": (0, 0, 1), "radius": 0.1, "height": 0.0}, "height"),
    ({"kind": "Plane", "axis": (0.0, 0.0, 0.0)}, "axis"),
    ({"kind": "Sphere", "radius": float("nan")}, "radius"),
    ({"kind": "Sphere", "radius": 0.1, "colour": (0.1, 2.0, 0.1)}, "colour"),
    ({"kind": "Sphere", "radius": 0.1, "tracking_id": -1}, "tracking_id"),
    ({"kind": "Plane", "axis": (0, 0, 1), "hessian": float("inf")}, "hessian"),
]


@pytest.mark.parametrize(("fields", "fragment"), CLIENT_IMPOSSIBLE)
def test_the_client_refuses_an_impossible_primitive(fields: dict[str, Any], fragment: str) -> None:
    with pytest.raises(ValueError, match=fragment):
        ScenePrimitive("p", centre=(0.0, 0.0, 0.0), **fields)


def test_the_client_centre_must_be_finite() -> None:
    with pytest.raises(ValueError, match="centre"):
        ScenePrimitive("p", "Sphere", centre=(0.0, float("nan"), 0.0), radius=0.1)
    assert ScenePrimitive("p", "Sphere", centre=(0.0, 0.0, 0.0), radius=0.1).directives()
