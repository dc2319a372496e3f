"""A stored primitive as triples, and back: the one writer and reader of a scene's primitives.

An experienced scene ``<scene> engram:hasPrimitive <scene>-0, <scene>-1, ...``; each primitive
is its kind (``rdf:type engram:Sphere``), its id (``rdfs:label``) and one literal per attribute,
named as in Engram's ontology (:data:`kg.primitive.ATTRIBUTES`). The scene memory writes them
with :func:`write_primitive` (``reasoners.persist.write_item``); the views, the episodes' scene
channel and anyone else read them back with :func:`read_scene` or :func:`read_primitive`, so
that what is read is exactly what was written:

>>> from kg import Store
>>> from ontologies.vocab import EPISODIC, HAS_PRIMITIVE, engram
>>> store = Store()
>>> ball = Primitive("ball", "Sphere", centre=(0.3, 0.3, 0.3), radius=0.05, tracking_id=7)
>>> scene = engram("Scene-1-experience-1")
>>> member = engram("Scene-1-experience-1-0")
>>> with store.transaction() as tx:
...     tx.insert(scene, HAS_PRIMITIVE, member, EPISODIC)
...     write_primitive(tx, member, ball, EPISODIC)
>>> read_scene(store, scene, EPISODIC) == [(member, ball)]
True
"""

from pyoxigraph import Literal, NamedNode

from kg.errors import InvalidPrimitiveError
from kg.primitive import ATTRIBUTES, KINDS, Kind, Primitive
from kg.transaction import QuadReader, Transaction
from ontologies.vocab import ENGRAM_NS, HAS_PRIMITIVE, RDF_TYPE, RDFS_LABEL, engram

__all__ = ["read_primitive", "read_scene", "write_primitive"]

_KINDS: dict[str, Kind] = {engram(kind).value: kind for kind in KINDS}


def write_primitive(
    tx: Transaction, iri: NamedNode, primitive: Primitive, graph: NamedNode
) -> None:
    """Store ``primitive`` as ``iri`` in ``graph``: its kind, its id and one literal per set
    attribute (``xsd:double``, ``xsd:integer`` for the tracking id)."""
    tx.insert(iri, RDF_TYPE, engram(primitive.kind), graph)
    tx.insert(iri, RDFS_LABEL, Literal(primitive.id), graph)
    for name, value in primitive.attributes().items():
        tx.insert(iri, engram(name), Literal(value), graph)


def read_primitive(store: QuadReader, iri: NamedNode, graph: NamedNode) -> Primitive | None:
    """The primitive ``iri`` as :func:`write_primitive` wrote it into ``graph`` (the episodic
    graph, or the trash after forgetting); None when ``graph`` holds no valid primitive there
    (no kind, no centre, an attribute out of range)."""
    kind: Kind | None = None
    label: str | None = None
    attributes: dict[str, float | int] = {}
    for quad in store.quads(iri, None, None, graph):
        value = quad.object
        if quad.predicate == RDF_TYPE and isinstance(value, NamedNode):
            kind = _KINDS.get(value.value, kind)
        elif quad.predicate == RDFS_LABEL and isinstance(value, Literal):
            label = label if label is not None else value.value
        elif isinstance(value, Literal) and quad.predicate.value.startswith(ENGRAM_NS):
            name = quad.predicate.value[len(ENGRAM_NS) :]
            if name in ATTRIBUTES and name not in attributes:
                attributes[name] = _number(value)
    if kind is None:
        return None
    try:
        return Primitive.from_attributes(
            label if label is not None else iri.value.rsplit("#", 1)[-1], kind, attributes
        )
    except InvalidPrimitiveError:
        return None


def read_scene(
    store: QuadReader, scene: NamedNode, graph: NamedNode
) -> list[tuple[NamedNode, Primitive]]:
    """The primitives of the stored scene ``scene`` in ``graph``, in the order they were
    written (``<scene>-0``, ``-1``, ..., ``-10``), each with its IRI; members that hold no
    valid primitive are left out."""
    members = [
        quad.object
        for quad in store.quads(scene, HAS_PRIMITIVE, None, graph)
        if isinstance(quad.object, NamedNode)
    ]
    members.sort(key=lambda member: (len(member.value), member.value))
    read = ((member, read_primitive(store, member, graph)) for member in members)
    return [(member, primitive) for member, primitive in read if primitive is not None]


def _number(literal: Literal) -> float | int:
    """A stored attribute's value: an int for ``xsd:integer``, else a float (nan when the
    lexical form is no number, which the primitive then refuses)."""
    try:
        if literal.datatype.value.endswith("#integer"):
            return int(literal.value)
        return float(literal.value)
    except ValueError:
        return float("nan")
