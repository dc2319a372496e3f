"""The memory as one OWL 2 DL ontology that Protégé, the OWL API and owlready2 open.

The export holds the chosen graphs under a single ``owl:Ontology`` header, with a declaration for
every entity (the OWL API turns undeclared properties into annotation properties), class
expressions as blank nodes again, and cardinalities typed ``xsd:nonNegativeInteger`` (the store
canonicalises them to ``xsd:integer``).

>>> from kg.store import Store
>>> from kg.ontology import ensure_ontology
>>> store = Store()
>>> _ = ensure_ontology(store)
>>> b"owl:Ontology" in export(store, ["tbox"], "turtle")
True
"""

import datetime as dt
import re
from collections import defaultdict
from collections.abc import Iterable, Sequence
from typing import Literal as Lit

from pyoxigraph import BlankNode, Literal, NamedNode, RdfFormat, Triple, serialize

from kg.export_scenes import SCENE_GRAPHS, scene_axioms
from kg.skolem import Deskolemiser
from kg.store import Store
from ontologies.vocab import (
    CARDINALITY_PREDICATES,
    DCTERMS_CREATED,
    EXPORT_ONTOLOGY_IRI,
    GRAPHS,
    OWL_ANNOTATION_PROPERTY,
    OWL_CLASS,
    OWL_DATATYPE_PROPERTY,
    OWL_NAMED_INDIVIDUAL,
    OWL_NS,
    OWL_OBJECT_PROPERTY,
    OWL_ON_CLASS,
    OWL_ON_PROPERTY,
    OWL_ONTOLOGY,
    OWL_VERSION_IRI,
    PREFIXES,
    RDF_NS,
    RDF_TYPE,
    RDFS_COMMENT,
    RDFS_LABEL,
    RDFS_NS,
    RDFS_SEEALSO,
    TBOX,
    XSD_DATETIME,
    XSD_NON_NEGATIVE_INTEGER,
    XSD_NS,
)

__all__ = [
    "DEFAULT_GRAPHS",
    "FORMATS",
    "ExportFormat",
    "export",
    "export_triples",
    "millisecond_time",
    "typed_cardinality",
]

ExportFormat = Lit["rdfxml", "turtle"]
FORMATS: dict[str, tuple[RdfFormat, str]] = {
    "rdfxml": (RdfFormat.RDF_XML, "application/rdf+xml"),
    "turtle": (RdfFormat.TURTLE, "text/turtle"),
}
DEFAULT_GRAPHS = ("tbox", "memory")
"""What an export holds unless asked otherwise; add "episodic" for the experienced scenes."""

_BUILTIN = (RDF_NS, RDFS_NS, OWL_NS, XSD_NS)
_ENTITY_KINDS = frozenset(
    {
        OWL_CLASS,
        OWL_OBJECT_PROPERTY,
        OWL_DATATYPE_PROPERTY,
        OWL_ANNOTATION_PROPERTY,
        OWL_NAMED_INDIVIDUAL,
        NamedNode(RDFS_NS + "Datatype"),
    }
)
_CLASS_POSITIONS = frozenset(
    NamedNode(ns + name)
    for ns, name in [
        (RDFS_NS, "subClassOf"),
        (OWL_NS, "equivalentClass"),
        (OWL_NS, "disjointWith"),
    ]
)


def export(store: Store, graphs: Sequence[str] = DEFAULT_GRAPHS, format: str = "rdfxml") -> bytes:
    """Serialise ``graphs`` of ``store`` as one ontology in ``format`` ("rdfxml" or "turtle").

    Raises ``ValueError`` naming the accepted values for an unknown graph or format.
    """
    if format not in FORMATS:
        raise ValueError(f"format: got {format!r}, expected one of {', '.join(FORMATS)}")
    rdf_format, _ = FORMATS[format]
    triples = export_triples(store, graphs)
    if rdf_format == RdfFormat.RDF_XML:
        _require_xml_characters(triples)
    body = serialize(triples, format=rdf_format, prefixes=PREFIXES)
    assert body is not None  # serialize returns bytes when given no output
    if rdf_format == RdfFormat.RDF_XML:
        # XML parsers turn a raw carriage return into a line feed; only a character reference
        # keeps it. The serialiser writes "\n" line ends, so every "\r" is inside a literal.
        body = body.replace(b"\r", b"&#13;")
    return body


def export_triples(store: Store, graphs: Sequence[str] = DEFAULT_GRAPHS) -> list[Triple]:
    """The triples of an export: header, the graphs' content, and missing declarations."""
    unknown = [name for name in graphs if name not in GRAPHS]
    if unknown or not graphs:
        raise ValueError(
            f"graphs: got {list(graphs)!r}, expected a non-empty list from {', '.join(GRAPHS)}"
        )
    deskolemise = Deskolemiser()
    content: dict[Triple, None] = {}  # ordered and without duplicates
    for name in graphs:
        for quad in store.quads(graph=GRAPHS[name]):
            content[deskolemise.triple(millisecond_time(typed_cardinality(quad.triple)))] = None
    for name in graphs:
        if name in SCENE_GRAPHS:  # so that a DL reasoner can classify the scenes
            content.update(dict.fromkeys(scene_axioms(store, name)))
    headers = {t.subject for t in content if t.predicate == RDF_TYPE and t.object == OWL_ONTOLOGY}
    sources = [t.object for t in content if t.subject in headers and t.predicate == OWL_VERSION_IRI]
    # Sorted so that two exports of the same memory differ only in blank node labels.
    body = _unshare(sorted((t for t in content if t.subject not in headers), key=_sort_key))
    return _header(graphs, sources) + body + _declarations(body, _tbox_kinds(store))


def _unshare(triples: list[Triple]) -> list[Triple]:
    """Give every use of a blank node its own copy of the node's description.

    The store may share one class-expression node between several axioms (the scene memory
    keeps one node per restriction ``≥n p.T`` for all the classes that use it); the OWL 2 RDF
    mapping, and so OWL 2 DL and the OWL API, want each anonymous expression used once.

    >>> from pyoxigraph import BlankNode, NamedNode
    >>> r, p = BlankNode(), NamedNode("http://x/p")
    >>> a, b = NamedNode("http://x/a"), NamedNode("http://x/b")
    >>> out = _unshare([Triple(a, p, r), Triple(b, p, r), Triple(r, p, a)])
    >>> len(out), len({t.object for t in out if t.predicate == p and t.subject in (a, b)})
    (4, 2)
    """
    uses: dict[BlankNode, int] = defaultdict(int)
    described: dict[BlankNode, list[Triple]] = defaultdict(list)
    for t in triples:
        if isinstance(t.object, BlankNode):
            uses[t.object] += 1
        if isinstance(t.subject, BlankNode):
            described[t.subject].append(t)
    if all(n <= 1 for n in uses.values()):
        return triples
    out: list[Triple] = []

    def copy(node: BlankNode, path: frozenset[BlankNode]) -> BlankNode:
        fresh = BlankNode()
        for t in described.get(node, ()):
            obj = t.object
            if isinstance(obj, BlankNode) and obj not in path:
                obj = copy(obj, path | {node})
            out.append(Triple(fresh, t.predicate, obj))
        return fresh

    seen: set[BlankNode] = set()
    for t in triples:
        node = t.object
        if isinstance(node, BlankNode) and uses[node] > 1:
            if node in seen:
                t = Triple(t.subject, t.predicate, copy(node, frozenset()))
            seen.add(node)
        out.append(t)
    return out


def _tbox_kinds(store: Store) -> dict[NamedNode, NamedNode]:
    """The kind the T-Box gives each entity, so an export without the T-Box still declares them
    as what they are (an annotation on a class must not turn into a data property)."""
    kinds: dict[NamedNode, NamedNode] = {}
    for quad in store.quads(predicate=RDF_TYPE, graph=TBOX):
        if isinstance(quad.subject, NamedNode) and quad.object in _ENTITY_KINDS:
            kinds.setdefault(quad.subject, quad.object)  # type: ignore[arg-type]
    return kinds


_NOT_XML = re.compile("[\x00-\x08\x0b\x0c\x0e-\x1f\ud800-\udfff\ufffe\uffff]")


def _require_xml_characters(triples: list[Triple]) -> None:
    """RDF/XML cannot carry every string: XML 1.0 forbids most control characters."""
    for triple in triples:
        if isinstance(triple.object, Literal) and (bad := _NOT_XML.search(triple.object.value)):
            raise ValueError(
                f"format: the value of {triple.predicate} on {triple.subject} holds "
                f"U+{ord(bad.group()):04X}, which XML 1.0 cannot carry; export as turtle"
            )


def _sort_key(triple: Triple) -> tuple[bool, str, str, str]:
    subject = triple.subject
    return (isinstance(subject, BlankNode), str(subject), str(triple.predicate), str(triple.object))


def typed_cardinality(triple: Triple) -> Triple:
    """The store keeps cardinalities as xsd:integer; OWL wants xsd:nonNegativeInteger."""
    if triple.predicate in CARDINALITY_PREDICATES and isinstance(triple.object, Literal):
        return Triple(
            triple.subject,
            triple.predicate,
            Literal(triple.object.value, datatype=XSD_NON_NEGATIVE_INTEGER),
        )
    return triple


_SUBSECOND = re.compile(r"(T\d\d:\d\d:\d\d\.\d{3})\d+")


def millisecond_time(triple: Triple) -> Triple:
    """An ``xsd:dateTime`` cut to milliseconds: HermiT (Protégé's reasoner) refuses more digits.

    >>> from pyoxigraph import NamedNode
    >>> t = Literal("2026-01-02T22:06:03.008925+00:00", datatype=XSD_DATETIME)
    >>> millisecond_time(Triple(NamedNode("http://x/a"), NamedNode("http://x/p"), t)).object.value
    '2026-01-02T22:06:03.008+00:00'
    """
    value = triple.object
    if isinstance(value, Literal) and value.datatype == XSD_DATETIME:
        cut = _SUBSECOND.sub(r"\1", value.value, count=1)
        if cut != value.value:
            return Triple(triple.subject, triple.predicate, Literal(cut, datatype=XSD_DATETIME))
    return triple


def _header(graphs: Sequence[str], sources: Iterable[object]) -> list[Triple]:
    now = dt.datetime.now(dt.UTC).replace(microsecond=0)
    header = [
        Triple(EXPORT_ONTOLOGY_IRI, RDF_TYPE, OWL_ONTOLOGY),
        Triple(EXPORT_ONTOLOGY_IRI, RDFS_LABEL, Literal("Engram memory export", language="en")),
        Triple(
            EXPORT_ONTOLOGY_IRI,
            RDFS_COMMENT,
            Literal(f"Graphs exported from an Engram store: {', '.join(graphs)}.", language="en"),
        ),
        Triple(
            EXPORT_ONTOLOGY_IRI, DCTERMS_CREATED, Literal(now.isoformat(), datatype=XSD_DATETIME)
        ),
        Triple(DCTERMS_CREATED, RDF_TYPE, OWL_ANNOTATION_PROPERTY),
    ]
    header += [
        Triple(EXPORT_ONTOLOGY_IRI, RDFS_SEEALSO, source)
        for source in sources
        if isinstance(source, NamedNode)
    ]
    return header


def _declarations(triples: list[Triple], known: dict[NamedNode, NamedNode]) -> list[Triple]:
    """Declarations for the IRIs the triples use but do not declare.

    An entity the T-Box knows gets its T-Box kind. Otherwise the kind follows from use: a class
    where a class must stand, an individual typed by a class, and a property by its values (all
    literals: data property; all resources: object property; mixed: annotation property, the
    only kind OWL 2 DL lets take both).
    """
    declared = {t.subject for t in triples if t.predicate == RDF_TYPE and t.object in _ENTITY_KINDS}
    needed: dict[NamedNode, NamedNode] = {}
    values: dict[NamedNode, set[bool]] = defaultdict(set)

    def need(term: object, kind: NamedNode) -> None:
        if isinstance(term, NamedNode) and term not in declared and not _builtin(term):
            needed.setdefault(term, known.get(term, kind))

    for t in triples:
        if t.predicate == RDF_TYPE:
            if isinstance(t.object, NamedNode) and not _builtin(t.object):
                need(t.object, OWL_CLASS)
                need(t.subject, OWL_NAMED_INDIVIDUAL)
        elif t.predicate in _CLASS_POSITIONS:
            need(t.subject, OWL_CLASS)
            need(t.object, OWL_CLASS)
        elif t.predicate == OWL_ON_CLASS:
            need(t.object, OWL_CLASS)
        elif t.predicate == OWL_ON_PROPERTY:
            need(t.object, OWL_OBJECT_PROPERTY)
        if not _builtin(t.predicate) and t.predicate not in declared:
            values[t.predicate].add(isinstance(t.object, Literal))
    for predicate, kinds in values.items():
        if predicate in known:
            needed[predicate] = known[predicate]
        elif kinds == {True}:
            needed[predicate] = OWL_DATATYPE_PROPERTY
        elif kinds == {False}:
            needed[predicate] = OWL_OBJECT_PROPERTY
        else:
            needed[predicate] = OWL_ANNOTATION_PROPERTY
    return [Triple(entity, RDF_TYPE, kind) for entity, kind in needed.items()]


def _builtin(term: NamedNode | BlankNode | object) -> bool:
    return isinstance(term, NamedNode) and term.value.startswith(_BUILTIN)
