"""Readable labels for learned classes, generated from their definitions.

A class ``Scene-N`` says nothing to an analyst or a Protégé user; its label spells out its
restrictions, one per signature key, in the signature's (sorted) order: ``≥1 sphereIsAboveOf.Plane``
reads "sphere above a plane", ``≥2 planeIsBelowOf.Sphere`` reads "plane below 2 spheres". The
short name stays as the class's ``skos:notation``.

>>> from ontologies.vocab import PLANE, SPHERE, engram
>>> from reasoners.signature import Signature
>>> label(Signature({(engram("sphereIsAboveOf"), PLANE): 1, (engram("planeIsBelowOf"), SPHERE): 2}))
'plane below 2 spheres; sphere above a plane'
"""

import re

from reasoners.signature import Signature

__all__ = ["label"]

_RELATIONS = {
    "isRightOf": "right of",
    "isLeftOf": "left of",
    "isBehindOf": "behind",
    "isInFrontOf": "in front of",
    "isAboveOf": "above",
    "isBelowOf": "below",
    "isParallelWith": "parallel with",
    "isPerpendicularWith": "perpendicular to",
    "isCoaxialWith": "coaxial with",
    "isAlongXWith": "aligned along x with",
    "isAlongYWith": "aligned along y with",
    "isAlongZWith": "aligned along z with",
}
_SPLIT = re.compile(r"^([a-z]+)(Is[A-Z]\w*)$")


def _local(iri: str) -> str:
    return iri.rsplit("#", 1)[-1].rsplit("/", 1)[-1]


def _phrase(prop: str, leaf: str, n: int) -> str:
    match = _SPLIT.match(_local(prop))
    noun = _local(leaf).lower()
    objects = f"a {noun}" if n == 1 else f"{n} {noun}s"
    if match is None:  # a property this module does not know: say it as it is
        return f"{_local(prop)} {objects}"
    subject, relation = match.group(1), match.group(2)
    words = _RELATIONS.get(relation[0].lower() + relation[1:], relation)
    return f"{subject} {words} {objects}"


def label(signature: Signature) -> str:
    """The label of a class with this signature (its restrictions, in order, as phrases)."""
    return "; ".join(_phrase(prop.value, leaf.value, n) for (prop, leaf), n in signature.items())
