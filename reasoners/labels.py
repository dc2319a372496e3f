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

from pyoxigraph import NamedNode

from reasoners.signature import Signature

__all__ = ["RELATION_WORDS", "label", "local"]

RELATION_WORDS = {
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
"""Each spatial relation (a scene property's local name without its subject's kind) in words,
as the labels and the explanations (:mod:`reasoners.explain`) say it."""
_SPLIT = re.compile(r"^([a-z]+)(Is[A-Z]\w*)$")


def local(iri: NamedNode | str) -> str:
    """The local name of an IRI (after ``#`` or the last ``/``).

    >>> local("https://example.org/engram#Scene-3"), local(NamedNode("https://example.org/a/b"))
    ('Scene-3', 'b')
    """
    text = iri.value if isinstance(iri, NamedNode) else iri
    return text.rsplit("#", 1)[-1].rsplit("/", 1)[-1]


def _phrase(prop: str, leaf: str, n: int) -> str:
    match = _SPLIT.match(local(prop))
    noun = local(leaf).lower()
    objects = f"a {noun}" if n == 1 else f"{n} {noun}s"
    if match is None:  # a property this module does not know: say it as it is
        return f"{local(prop)} {objects}"
    subject, relation = match.group(1), match.group(2)
    words = RELATION_WORDS.get(relation[0].lower() + relation[1:], relation)
    return f"{subject} {words} {objects}"


def label(signature: Signature) -> str:
    """The label of a class with this signature (its restrictions, in order, as phrases)."""
    return "; ".join(_phrase(prop.value, leaf.value, n) for (prop, leaf), n in signature.items())
