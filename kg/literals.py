"""Literals whose datatype Oxigraph would rewrite, stored under a datatype it keeps.

Oxigraph stores the XSD integer subtypes (``xsd:byte``, ``xsd:long``, ``xsd:nonNegativeInteger``
and the nine others) as ``xsd:integer`` and ``xsd:dateTimeStamp`` as ``xsd:dateTime``: the value
survives, the datatype does not, and with it what OWL needs (``"300"^^xsd:byte`` is not a byte;
``∃p.xsd:nonNegativeInteger`` must see the type). So those thirteen datatypes are written to the
store in a namespace of Engram's own, which Oxigraph keeps verbatim, and every read of the
:class:`kg.store.Store` maps them back: ``"5"^^xsd:byte`` goes in and comes out as itself.
See docs/literals.md for what this costs (SPARQL compares these literals as strings of an unknown
datatype) and what the store still canonicalises (the lexical forms of the core datatypes).

>>> byte = Literal("5", datatype=NamedNode(XSD_NS + "byte"))
>>> stored = to_store(byte)
>>> stored.datatype.value
'https://w3id.org/engram/kept-datatype#byte'
>>> from_store(stored) == byte
True
"""

import re
from collections.abc import Iterable
from typing import TypeVar

from pyoxigraph import Literal, NamedNode, Quad

from ontologies.vocab import XSD_NS

__all__ = [
    "KEPT",
    "REWRITTEN",
    "from_store",
    "kept_text",
    "ntriples_to_store",
    "quad_from_store",
    "quads_to_store",
    "to_store",
]

KEPT = "https://w3id.org/engram/kept-datatype#"
"""The namespace the rewritten datatypes are stored under: ``KEPT + "byte"`` is ``xsd:byte``."""
REWRITTEN = frozenset(
    [
        "byte",
        "short",
        "int",
        "long",
        "unsignedByte",
        "unsignedShort",
        "unsignedInt",
        "unsignedLong",
        "positiveInteger",
        "negativeInteger",
        "nonPositiveInteger",
        "nonNegativeInteger",
        "dateTimeStamp",
    ]
)
"""The XSD datatypes (local names) whose literals Oxigraph stores under another datatype."""

_TO_STORE = re.compile(
    rb"\^\^<http://www\.w3\.org/2001/XMLSchema#(" + "|".join(sorted(REWRITTEN)).encode() + rb")>"
)
_KEPT_BYTES, _XSD_BYTES = KEPT.encode(), XSD_NS.encode()
_Term = TypeVar("_Term")


def to_store(term: _Term) -> _Term:
    """The term to write: a literal of a rewritten datatype under :data:`KEPT`, else ``term``."""
    if isinstance(term, Literal):
        datatype = term.datatype.value
        if datatype.startswith(XSD_NS) and datatype[len(XSD_NS) :] in REWRITTEN:
            kept = Literal(term.value, datatype=NamedNode(KEPT + datatype[len(XSD_NS) :]))
            return kept  # type: ignore[return-value]
    return term


def from_store(term: _Term) -> _Term:
    """The term as written: a literal under :data:`KEPT` back in XSD, else ``term``."""
    if isinstance(term, Literal):
        datatype = term.datatype.value
        if datatype.startswith(KEPT):
            original = Literal(term.value, datatype=NamedNode(XSD_NS + datatype[len(KEPT) :]))
            return original  # type: ignore[return-value]
    return term


def quad_from_store(quad: Quad) -> Quad:
    """The quad as written: its literal object through :func:`from_store`."""
    obj = quad.object
    if type(obj) is Literal and obj.datatype.value.startswith(KEPT):
        return Quad(quad.subject, quad.predicate, from_store(obj), quad.graph_name)
    return quad


_REWRITTEN_TYPES = frozenset(NamedNode(XSD_NS + name) for name in REWRITTEN)


def quads_to_store(quads: Iterable[Quad]) -> list[Quad]:
    """The quads to write, each literal object through :func:`to_store` (a quad whose object
    keeps its datatype is passed on as it is, not rebuilt: a score view's write holds
    thousands of them)."""
    out = []
    for quad in quads:
        obj = quad.object
        if type(obj) is Literal and obj.datatype in _REWRITTEN_TYPES:
            quad = Quad(quad.subject, quad.predicate, to_store(obj), quad.graph_name)
        out.append(quad)
    return out


def ntriples_to_store(data: bytes) -> bytes:
    """N-Triples (or N-Quads) with the rewritten datatypes moved under :data:`KEPT`.

    >>> ntriples_to_store(b'<a> <p> "5"^^<http://www.w3.org/2001/XMLSchema#byte> .')
    b'<a> <p> "5"^^<https://w3id.org/engram/kept-datatype#byte> .'
    """
    if b"XMLSchema#" not in data:
        return data
    return _TO_STORE.sub(lambda m: b"^^<" + KEPT.encode() + m.group(1) + b">", data)


def kept_text(data: bytes) -> bytes:
    """Serialised terms (N-Triples, SPARQL results in any format) with :data:`KEPT` back as XSD.

    The namespace is Engram's own and only ever names these datatypes, so a plain replacement
    is exact.
    """
    return data.replace(_KEPT_BYTES, _XSD_BYTES)
