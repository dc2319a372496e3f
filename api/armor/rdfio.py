"""Reading and writing a reference's ontology: RDF/XML, Turtle, N-Triples and OWL/XML.

The format is taken from the file's content (an XML root of ``rdf:RDF`` or OWL's ``Ontology``),
then its extension, so Protégé's ``.owl`` files load whichever syntax they were saved in.

>>> detect_format(b'<?xml version="1.0"?>\\n<rdf:RDF xmlns:rdf="http://x/"/>', "x.owl")
'rdfxml'
>>> detect_format(b"@prefix : <http://ex.org/> .", "x.ttl")
'turtle'
"""

import os
import re
import tempfile
from pathlib import Path

from pyoxigraph import NamedNode, Quad, RdfFormat, Triple, parse, serialize

from api.armor.errors import ResourceError
from api.armor.owlxml import OwlXmlError, owlxml_triples
from kg.export import typed_cardinality
from kg.skolem import Deskolemiser, Skolemiser
from ontologies.vocab import (
    OWL_ONTOLOGY,
    PREFIXES,
    RDF_TYPE,
)

__all__ = ["FORMATS", "detect_format", "parse_ontology", "write_ontology"]

FORMATS = {
    "rdfxml": RdfFormat.RDF_XML,
    "turtle": RdfFormat.TURTLE,
    "ntriples": RdfFormat.N_TRIPLES,
}
"""Formats pyoxigraph reads and writes; ``owlxml`` is read by :mod:`api.armor.owlxml`."""
_XML_ROOT = re.compile(rb"<(?![?!])([\w.-]+:)?([\w.-]+)")


def detect_format(content: bytes, name: str) -> str:
    """``rdfxml``, ``owlxml``, ``turtle`` or ``ntriples`` for a document and its file name."""
    head = content[:4096].lstrip()
    if head.startswith(b"\xef\xbb\xbf"):
        head = head[3:]
    if head.startswith(b"<?xml") or head.startswith(b"<!") or re.match(rb"<[\w:.-]+[\s>]", head):
        for match in _XML_ROOT.finditer(content[:65536]):
            if match.group(2) == b"Ontology":
                return "owlxml"
            if match.group(2) == b"RDF":
                return "rdfxml"
        return "rdfxml"
    suffix = Path(name.split("?")[0]).suffix.lower()
    if suffix == ".nt":
        return "ntriples"
    if suffix == ".owx":
        return "owlxml"
    return "turtle"  # Turtle also reads N-Triples


def parse_ontology(content: bytes, *, name: str, base_iri: str | None) -> tuple[list[Triple], str]:
    """The triples of an ontology document (blank nodes made skolem IRIs) and its format.

    Raises :class:`ResourceError` with the parser's message if the document is malformed.
    """
    kind = detect_format(content, name)
    skolem = Skolemiser()
    try:
        if kind == "owlxml":
            raw = owlxml_triples(content)
        else:
            raw = [q.triple for q in parse(content, format=FORMATS[kind], base_iri=base_iri)]
    except (SyntaxError, OwlXmlError, ValueError) as error:
        raise ResourceError(f"args[0]: {name} is not valid {_label(kind)}: {error}") from None
    triples = [Triple(skolem.term(t.subject), t.predicate, skolem.term(t.object)) for t in raw]
    return triples, kind


def _label(kind: str) -> str:
    return {"rdfxml": "RDF/XML", "owlxml": "OWL/XML", "turtle": "Turtle", "ntriples": "N-Triples"}[
        kind
    ]


def write_ontology(quads: list[Quad], path: Path, kind: str) -> None:
    """Write triples to ``path`` atomically (a temporary file renamed over it).

    OWL/XML references are written as RDF/XML. Raises :class:`ResourceError` on failure.
    """
    deskolemise = Deskolemiser()
    triples = [deskolemise.triple(typed_cardinality(q.triple)) for q in quads]
    rdf_format = FORMATS.get(kind, RdfFormat.RDF_XML)
    try:
        body = serialize(triples, format=rdf_format, prefixes=PREFIXES)
        assert body is not None
        path.parent.mkdir(parents=True, exist_ok=True)
        handle, temp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.")
        with os.fdopen(handle, "wb") as out:
            out.write(body)
            out.flush()
            os.fsync(out.fileno())
        os.replace(temp, path)
    except (OSError, ValueError) as error:
        raise ResourceError(f"args[0]: cannot write {path}: {error}") from None


def file_kind(path: str) -> str:
    """The format to write a new file in, from its extension."""
    suffix = Path(path).suffix.lower()
    return {".ttl": "turtle", ".nt": "ntriples"}.get(suffix, "rdfxml")


def ontology_iri(triples: list[Triple]) -> NamedNode | None:
    """The IRI of the document's ``owl:Ontology``, if it names one."""
    for triple in triples:
        if (
            triple.predicate == RDF_TYPE
            and triple.object == OWL_ONTOLOGY
            and isinstance(triple.subject, NamedNode)
        ):
            return triple.subject
    return None
