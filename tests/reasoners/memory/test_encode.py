"""Encoding: SIT v1 relations (frame x right, y behind, z up) and the full-form signature."""

import pytest
from pyoxigraph import NamedNode

from kg import Store, ensure_ontology
from kg.primitive import Primitive
from ontologies.vocab import CONE, CYLINDER, PLANE, SPHERE, engram
from reasoners.encode import Encoder
from reasoners.errors import InvalidSceneError
from reasoners.policy import load_policy
from reasoners.signature import Signature

from .conftest import plane, sphere, worked_example


@pytest.fixture(scope="module")
def encoder() -> Encoder:
    store = Store()
    ensure_ontology(store)
    return Encoder.from_store(store, load_policy(store))


def names(encoder: Encoder, scene: list[Primitive]) -> set[tuple[str, str, str]]:
    return {
        (scene[r.subject].id, r.relation.value.rsplit("#")[-1], scene[r.object].id)
        for r in encoder.relations(scene)
    }


def sig(**counts: int) -> Signature:
    leaves = {"Sphere": SPHERE, "Plane": PLANE, "Cone": CONE, "Cylinder": CYLINDER}
    out: dict[tuple[NamedNode, NamedNode], int] = {}
    for name, n in counts.items():
        prop, leaf = name.split("__")
        out[(engram(prop), leaves[leaf])] = n
    return Signature(out)


def test_worked_example_relations_and_signature(encoder: Encoder) -> None:
    scene = worked_example()
    assert names(encoder, scene) == {("S", "isAboveOf", "P"), ("S", "isBehindOf", "P")}
    assert encoder.signature(scene) == sig(
        sphereIsAboveOf__Plane=1,
        sphereIsBehindOf__Plane=1,
        planeIsBelowOf__Sphere=1,
        planeIsInFrontOf__Sphere=1,
    )


@pytest.mark.parametrize(
    ("offset", "relation"),
    [((0.1, 0, 0), "isRightOf"), ((0, 0.1, 0), "isBehindOf"), ((0, 0, 0.1), "isAboveOf")],
)
def test_frame_is_x_right_y_behind_z_up(
    encoder: Encoder, offset: tuple[float, float, float], relation: str
) -> None:
    a, b = sphere("a", 0, 0, 0), sphere("b", *offset)
    assert (("b", relation, "a")) in names(encoder, [a, b])
    assert not any(r[0] == "a" and r[1] == relation for r in names(encoder, [a, b]))


def test_thresholds_are_strict_for_order_and_inclusive_for_alignment(encoder: Encoder) -> None:
    a, b = sphere("a", 0, 0, 0), sphere("b", 0.05, 0, 0)  # exactly the 0.05 m threshold
    assert names(encoder, [a, b]) == {
        ("a", "isAlongXWith", "b"),
        ("a", "isAlongYWith", "b"),
        ("a", "isAlongZWith", "b"),
    }


def test_parallel_perpendicular_and_coaxial(encoder: Encoder) -> None:
    up = Primitive("up", "Cylinder", centre=(0, 0, 0), axis=(0, 0, 1))
    above = Primitive("above", "Cylinder", centre=(0, 0, 0.5), axis=(0, 0, 2))
    side = Primitive("side", "Cone", centre=(1, 0, 0), axis=(1, 0, 0))
    found = names(encoder, [up, above, side])
    assert ("up", "isParallelWith", "above") in found
    assert ("up", "isCoaxialWith", "above") in found
    assert ("up", "isPerpendicularWith", "side") in found
    assert ("above", "isPerpendicularWith", "side") in found
    assert not {("up", "isParallelWith", "side"), ("up", "isCoaxialWith", "side")} & found


def test_two_spheres_above_one_plane_is_more_specific(encoder: Encoder) -> None:
    one = encoder.signature([sphere("s", 0.3, 0.1, 0.3), plane("p", 0.3, 0.1, 0.1)])
    two = encoder.signature(
        [sphere("s1", 0.29, 0.1, 0.3), sphere("s2", 0.31, 0.1, 0.3), plane("p", 0.3, 0.1, 0.1)]
    )
    assert two.satisfies(one) and not one.satisfies(two)
    assert two[(engram("planeIsBelowOf"), SPHERE)] == 2
    assert two[(engram("sphereIsAboveOf"), PLANE)] == 1  # one distinct plane
    assert two.complexity > one.complexity


def test_scene_and_class_count_alike_so_a_scene_meets_its_own_signature(encoder: Encoder) -> None:
    scene = [sphere("s1", 0, 0, 0.2), sphere("s2", 0.2, 0, 0.2), plane("p", 0.1, 0, 0)]
    signature = encoder.signature(scene)
    assert signature.satisfies(signature)
    assert sum(signature.values()) == signature.complexity


@pytest.mark.parametrize(
    ("cue", "fragment"),
    [
        ([], "expected at least one triple"),
        ([("Sphere", "isAboveOf")], "expected (subject type, relation, object type)"),
        ([("Ball", "isAboveOf", "Plane")], "subject type: got 'Ball'"),
        ([("Sphere", "isAboveOf", "Table")], "object type: got 'Table'"),
        ([("Sphere", "above", "Plane")], "relation: got 'above', expected one of isAboveOf"),
    ],
)
def test_bad_cue_relations_are_named(encoder: Encoder, cue: list, fragment: str) -> None:
    with pytest.raises(InvalidSceneError) as caught:
        encoder.cue_signature(cue)
    assert fragment in str(caught.value)


def test_cue_of_relations_matches_the_scene_signature(encoder: Encoder) -> None:
    assert encoder.cue_signature(
        [("Sphere", "isAboveOf", "Plane"), ("Sphere", "isBehindOf", "Plane")]
    ) == encoder.signature(worked_example())
