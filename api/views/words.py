"""Class definitions in words: ``sphereIsAboveOf ≥1 Plane`` reads "a sphere above a plane".

A relation is said in the words of the classes' stored labels
(:data:`reasoners.labels.RELATION_WORDS`).

>>> words([("sphereIsAboveOf", "Plane", 1), ("planeIsBelowOf", "Sphere", 1)])
'a sphere above a plane, and a plane below a sphere'
>>> words([("cylinderIsLeftOf", "Cylinder", 2)])
'a cylinder left of 2 cylinders'
>>> relation_of("coneIsAlongZWith")
('cone', 'isAlongZWith')
"""

from collections.abc import Iterable

from reasoners.labels import RELATION_WORDS

__all__ = ["relation_of", "words"]

_TYPES = ("sphere", "cylinder", "cone", "plane")


def relation_of(scene_property: str) -> tuple[str, str]:
    """Split a scene property's local name into (subject type, relation); the subject type is
    empty when the name does not start with a primitive type."""
    for kind in _TYPES:
        rest = scene_property[len(kind) :]
        if scene_property.startswith(kind) and rest.startswith("Is"):
            return kind, "is" + rest[2:]
    return "", scene_property


def _noun(kind: str, n: int) -> str:
    return f"a {kind}" if n == 1 else f"{n} {kind}s"


def words(restrictions: Iterable[tuple[str, str, int]]) -> str:
    """The definition ``⊓ (≥n property.Type)`` as a sentence, one clause per restriction."""
    clauses = []
    for scene_property, target, n in restrictions:
        kind, relation = relation_of(scene_property)
        phrase = RELATION_WORDS.get(relation, relation)
        clauses.append(f"a {kind or 'thing'} {phrase} {_noun(target.lower(), n)}")
    if len(clauses) <= 1:
        return "".join(clauses)
    return ", ".join(clauses[:-1]) + ", and " + clauses[-1]
