"""Primitive validation: each bad field gets a ValueError naming field, value, expectation."""

import pytest

from kg.errors import InvalidPrimitiveError
from kg.primitive import Primitive

GOOD = {"id": "a", "kind": "Cylinder", "centre": (0, 0, 0), "axis": (0, 0, 1)}


@pytest.mark.parametrize(
    ("changes", "fragment"),
    [
        ({"id": ""}, "primitive id: got ''"),
        ({"kind": "Cube"}, "kind: got 'Cube', expected one of Sphere, Cylinder, Cone, Plane"),
        ({"centre": (0, 0)}, "centre: got (0, 0), expected three finite numbers"),
        ({"centre": (0, 0, float("nan"))}, "centre: got nan, expected a finite number"),
        ({"centre": (0, "1", 0)}, "centre: got '1', expected a finite number"),
        ({"axis": None}, "axis: got None, expected a non-zero 3-vector"),
        ({"axis": (0, 0, 0)}, "axis: got (0, 0, 0), expected a non-zero 3-vector"),
        ({"kind": "Sphere"}, "axis: got (0, 0, 1), expected None (a sphere has no axis)"),
        ({"radius": -1.0}, "radius: got -1.0, expected a positive length in metres"),
        ({"radius": True}, "radius: got True, expected a finite number"),
        ({"height": 0}, "height: got 0, expected a positive length"),
        ({"apex": (0, 0, 1)}, "apex: got (0, 0, 1), expected None (only a Cone has it)"),
        ({"hessian": 0.5}, "hessian: got 0.5, expected None (only a Plane has it)"),
        ({"colour": (0, 2, 0)}, "colour: got (0, 2, 0), expected three channels in [0, 1]"),
        ({"tracking_id": -3}, "tracking_id: got -3, expected a non-negative integer"),
        ({"tracking_id": 1.5}, "tracking_id: got 1.5, expected a non-negative integer"),
    ],
)
def test_bad_primitive_fields_are_named(changes: dict, fragment: str) -> None:
    with pytest.raises(InvalidPrimitiveError) as caught:
        Primitive(**{**GOOD, **changes})
    assert fragment in str(caught.value)
    assert isinstance(caught.value, ValueError)


def test_axis_is_normalised_and_numbers_become_floats() -> None:
    cone = Primitive("c", "Cone", centre=(1, 2, 3), axis=(0, 3, 4), apex=(1, 2, 4), height=1)
    assert cone.axis == pytest.approx((0.0, 0.6, 0.8))
    assert cone.centre == (1.0, 2.0, 3.0)
    assert cone.height == 1.0 and isinstance(cone.height, float)
    assert cone.orientable
    assert not Primitive("s", "Sphere", centre=(0, 0, 0)).orientable


def test_a_huge_axis_is_normalised_not_zeroed() -> None:
    plane = Primitive("t", "Plane", centre=(0, 0, 0), axis=(1e200, 1e200, 0))
    assert plane.axis == pytest.approx((2**-0.5, 2**-0.5, 0.0))


@pytest.mark.parametrize("axis", [(0.0, 0.0, 1e-12), (float("inf"), 0.0, 0.0)])
def test_an_axis_without_a_direction_is_refused(axis: tuple[float, float, float]) -> None:
    with pytest.raises(InvalidPrimitiveError, match="axis"):
        Primitive("t", "Plane", centre=(0, 0, 0), axis=axis)


CENTRE = {"centreX": 0.1, "centreY": 0.2, "centreZ": 0.3}


@pytest.mark.parametrize(
    ("attributes", "fragment"),
    [
        (CENTRE | {"volume": 1.0}, "attribute: got 'volume', expected one of centreX"),
        ({"centreX": 0.1, "centreZ": 0.3}, "primitive 'p': centre lacks its Y"),
        (CENTRE | {"colourR": 1.0, "colourG": 0.5}, "primitive 'p': colour lacks its B"),
        ({"radius": 0.1}, "primitive 'p': no centre (centreX/Y/Z)"),
        (CENTRE | {"trackingId": 3.5}, "tracking_id: got 3.5, expected a non-negative integer"),
    ],
)
def test_attributes_that_make_no_primitive_are_refused(
    attributes: dict[str, float], fragment: str
) -> None:
    with pytest.raises(InvalidPrimitiveError) as caught:
        Primitive.from_attributes("p", "Sphere", attributes)
    assert fragment in str(caught.value)


def test_attributes_read_back_as_the_primitive_they_came_from() -> None:
    cone = Primitive(
        "cone", "Cone", centre=(0, 0, 0.1), axis=(0, 0, -1), apex=(0, 0, 0.2), tracking_id=4
    )
    assert cone.attributes()["trackingId"] == 4
    assert Primitive.from_attributes("cone", "Cone", cone.attributes()) == cone
    whole = dict(cone.attributes(), trackingId=4.0)  # an INTEGER sent as a DOUBLE
    assert Primitive.from_attributes("cone", "Cone", whole) == cone
