"""Physical checks on primitive attributes where they enter: the client's Primitive
refuses what no primitive can be before sending it (the server refuses it at SCENE UPDATED,
storing nothing: tests/api/armor/test_numerals.py)."""

from typing import Any

import pytest

from api.client import Primitive, primitive_directives

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
        Primitive("p", centre=(0.0, 0.0, 0.0), **fields)


def test_the_client_centre_must_be_finite() -> None:
    with pytest.raises(ValueError, match="centre"):
        Primitive("p", "Sphere", centre=(0.0, float("nan"), 0.0), radius=0.1)
    assert primitive_directives(Primitive("p", "Sphere", centre=(0.0, 0.0, 0.0), radius=0.1))
