"""ADD, REMOVE, REPLACE, DISJOINT, MAKE EQUIVALENT, RENAME and ADD CARDINALITY MIN.

Each handler checks its arguments first (so a queued directive is known to be well-formed), then
queues itself if the reference buffers manipulations, then writes the OWL axiom's RDF mapping
into the reference's asserted graph. Entities need no declaration beforehand, as in ARMOR; the
handlers add the OWL declarations Protégé needs (``owl:NamedIndividual``, ``owl:Class``, …) when
the entity has none.
"""

import uuid
from collections.abc import Callable

from pyoxigraph import Literal, NamedNode, Quad

from api.armor.context import Context, Outcome
from api.armor.errors import UNSUPPORTED_TYPE, InvalidArgumentsError
from api.armor.names import is_value_type, to_literal
from kg.skolem import is_skolem
from ontologies.vocab import (
    OWL_CLASS,
    OWL_DATATYPE_PROPERTY,
    OWL_EQUIVALENT_CLASS,
    OWL_INTERSECTION_OF,
    OWL_MIN_QUALIFIED_CARDINALITY,
    OWL_NAMED_INDIVIDUAL,
    OWL_NS,
    OWL_OBJECT_PROPERTY,
    OWL_ON_CLASS,
    OWL_ON_PROPERTY,
    OWL_RESTRICTION,
    OWL_THING,
    RDF_FIRST,
    RDF_NIL,
    RDF_REST,
    RDF_TYPE,
    RDFS_SUBCLASSOF,
    SKOLEM_PREFIX,
    XSD_NON_NEGATIVE_INTEGER,
)

__all__ = ["HANDLERS"]

OWL_DIFFERENT_FROM = NamedNode(OWL_NS + "differentFrom")
OWL_ALL_DIFFERENT = NamedNode(OWL_NS + "AllDifferent")
OWL_DISTINCT_MEMBERS = NamedNode(OWL_NS + "distinctMembers")
OWL_DISJOINT_WITH = NamedNode(OWL_NS + "disjointWith")
OWL_ALL_DISJOINT_CLASSES = NamedNode(OWL_NS + "AllDisjointClasses")
OWL_MEMBERS = NamedNode(OWL_NS + "members")
_OK = Outcome


def _fresh() -> NamedNode:
    """A new node standing for a blank node (stored as a skolem IRI)."""
    return NamedNode(SKOLEM_PREFIX + uuid.uuid4().hex)


def _declare(ctx: Context, entity: NamedNode, kind: NamedNode) -> list[Quad]:
    """``entity rdf:type kind`` unless the entity already has a declaration."""
    reference = ctx.reference()
    if ctx.session.quads(reference, entity, RDF_TYPE, kind, graph=reference.asserted):
        return []
    if kind != OWL_NAMED_INDIVIDUAL:
        for quad in ctx.session.quads(reference, entity, RDF_TYPE, graph=reference.asserted):
            if isinstance(quad.object, NamedNode) and quad.object.value.startswith(OWL_NS):
                return []  # declared as something else already (punning is the user's choice)
    return [ctx.quad(entity, RDF_TYPE, kind)]


def _rdf_list(ctx: Context, items: list[NamedNode]) -> tuple[NamedNode, list[Quad]]:
    head: NamedNode = RDF_NIL
    quads: list[Quad] = []
    for item in reversed(items):
        cell = _fresh()
        quads += [ctx.quad(cell, RDF_FIRST, item), ctx.quad(cell, RDF_REST, head)]
        head = cell
    return head, quads


def _typed_value(ctx: Context, type_index: int, value_index: int) -> Literal | None:
    """The literal of args[value_index] typed by args[type_index], or None for an unknown type."""
    type_name = ctx.arg(type_index, "value type")
    value = ctx.arg(value_index, "value")
    if not is_value_type(type_name):
        return None
    return to_literal(type_name, value, field=f"args[{value_index}]")


def _unsupported(ctx: Context, prop: str, ind: str, verb: str, *, success: bool) -> Outcome:
    type_name = ctx.args[2]
    return Outcome(
        success=success,
        exit_code=UNSUPPORTED_TYPE,
        error_description=f"Value type {type_name} not supported. {prop}not {verb} {ind}.",
    )


# ADD -------------------------------------------------------------------------------------------


def add_ind(ctx: Context) -> Outcome:
    ind = ctx.name(0, "individual")
    if ctx.buffered():
        return _OK()
    ctx.write(
        insert=[ctx.quad(ind, RDF_TYPE, OWL_THING), *_declare(ctx, ind, OWL_NAMED_INDIVIDUAL)]
    )
    return _OK()


def add_class(ctx: Context) -> Outcome:
    cls = ctx.name(0, "class")
    if ctx.buffered():
        return _OK()
    ctx.write(insert=[ctx.quad(cls, RDFS_SUBCLASSOF, OWL_THING), *_declare(ctx, cls, OWL_CLASS)])
    return _OK()


def add_ind_class(ctx: Context) -> Outcome:
    ind, cls = ctx.name(0, "individual"), ctx.name(1, "class")
    if ctx.buffered():
        return _OK()
    ctx.write(
        insert=[
            ctx.quad(ind, RDF_TYPE, cls),
            *_declare(ctx, ind, OWL_NAMED_INDIVIDUAL),
            *_declare(ctx, cls, OWL_CLASS),
        ]
    )
    return _OK()


def add_class_class(ctx: Context) -> Outcome:
    sub, sup = ctx.name(0, "subclass"), ctx.name(1, "superclass")
    if ctx.buffered():
        return _OK()
    ctx.write(
        insert=[
            ctx.quad(sub, RDFS_SUBCLASSOF, sup),
            *_declare(ctx, sub, OWL_CLASS),
            *_declare(ctx, sup, OWL_CLASS),
        ]
    )
    return _OK()


def add_dataprop_ind(ctx: Context) -> Outcome:
    prop, ind = ctx.name(0, "data property"), ctx.name(1, "individual")
    value = _typed_value(ctx, 2, 3)
    if value is None:
        return _unsupported(ctx, ctx.args[0], ctx.args[1], "added to", success=True)
    if ctx.buffered():
        return _OK()
    ctx.write(
        insert=[
            ctx.quad(ind, prop, value),
            *_declare(ctx, prop, OWL_DATATYPE_PROPERTY),
            *_declare(ctx, ind, OWL_NAMED_INDIVIDUAL),
        ]
    )
    return _OK()


def add_objectprop_ind(ctx: Context) -> Outcome:
    prop, ind = ctx.name(0, "object property"), ctx.name(1, "individual")
    value = ctx.name(2, "value individual")
    if ctx.buffered():
        return _OK()
    ctx.write(
        insert=[
            ctx.quad(ind, prop, value),
            *_declare(ctx, prop, OWL_OBJECT_PROPERTY),
            *_declare(ctx, ind, OWL_NAMED_INDIVIDUAL),
            *_declare(ctx, value, OWL_NAMED_INDIVIDUAL),
        ]
    )
    return _OK()


def add_cardinality_min(ctx: Context) -> Outcome:
    cls, prop = ctx.name(0, "class"), ctx.name(1, "object property")
    count = ctx.arg(2, "cardinality")
    value_cls = ctx.name(3, "value class")
    if not count.isascii() or not count.isdigit():
        raise InvalidArgumentsError(
            f"args[2]: got {count!r}, expected a non-negative integer (ASCII digits)"
        )
    if ctx.buffered():
        return _OK()
    restriction = _fresh()
    number = Literal(str(int(count)), datatype=XSD_NON_NEGATIVE_INTEGER)
    ctx.write(
        insert=[
            ctx.quad(cls, RDFS_SUBCLASSOF, restriction),
            ctx.quad(restriction, RDF_TYPE, OWL_RESTRICTION),
            ctx.quad(restriction, OWL_ON_PROPERTY, prop),
            ctx.quad(restriction, OWL_MIN_QUALIFIED_CARDINALITY, number),
            ctx.quad(restriction, OWL_ON_CLASS, value_cls),
            *_declare(ctx, cls, OWL_CLASS),
            *_declare(ctx, value_cls, OWL_CLASS),
            *_declare(ctx, prop, OWL_OBJECT_PROPERTY),
        ]
    )
    return _OK()


# DISJOINT --------------------------------------------------------------------------------------


def _names(ctx: Context, what: str) -> list[NamedNode]:
    if len(ctx.args) < 2:
        raise InvalidArgumentsError(
            f"args: got {len(ctx.args)} {what}(s), expected at least 2 to make disjoint"
        )
    return [ctx.name(i, what) for i in range(len(ctx.args))]


def _different(ctx: Context, inds: list[NamedNode]) -> list[Quad]:
    unique = list(dict.fromkeys(inds))
    if len(unique) < 2:
        return []
    if len(unique) == 2:
        return [ctx.quad(unique[0], OWL_DIFFERENT_FROM, unique[1])]
    node = _fresh()
    head, cells = _rdf_list(ctx, unique)
    return [
        ctx.quad(node, RDF_TYPE, OWL_ALL_DIFFERENT),
        ctx.quad(node, OWL_DISTINCT_MEMBERS, head),
        *cells,
    ]


def _disjoint(ctx: Context, classes: list[NamedNode]) -> list[Quad]:
    unique = list(dict.fromkeys(classes))
    if len(unique) < 2:
        return []
    if len(unique) == 2:
        return [ctx.quad(unique[0], OWL_DISJOINT_WITH, unique[1])]
    node = _fresh()
    head, cells = _rdf_list(ctx, unique)
    return [
        ctx.quad(node, RDF_TYPE, OWL_ALL_DISJOINT_CLASSES),
        ctx.quad(node, OWL_MEMBERS, head),
        *cells,
    ]


def disjoint_ind(ctx: Context) -> Outcome:
    inds = _names(ctx, "individual")
    if ctx.buffered():
        return _OK()
    ctx.write(insert=_different(ctx, inds))
    return _OK()


def disjoint_class(ctx: Context) -> Outcome:
    classes = _names(ctx, "class")
    if ctx.buffered():
        return _OK()
    ctx.write(insert=_disjoint(ctx, classes))
    return _OK()


def _class_bindings(cls: NamedNode) -> dict[str, NamedNode | Literal]:
    """``class`` is a Python keyword, so it is bound through a dict."""
    return {"class": cls, "skolem": Literal(SKOLEM_PREFIX)}


def disjoint_ind_class(ctx: Context) -> Outcome:
    cls = ctx.name(0, "class")
    if ctx.buffered():
        return _OK()
    rows = ctx.session.select(ctx.reference(), "armor_class_instances", **_class_bindings(cls))
    inds = sorted((row["ind"] for row in rows if isinstance(row["ind"], NamedNode)), key=str)
    ctx.write(insert=_different(ctx, inds))
    return _OK()


def disjoint_class_class(ctx: Context) -> Outcome:
    cls = ctx.name(0, "class")
    if ctx.buffered():
        return _OK()
    rows = ctx.session.select(ctx.reference(), "armor_direct_subclasses", **_class_bindings(cls))
    subs = sorted((row["sub"] for row in rows if isinstance(row["sub"], NamedNode)), key=str)
    ctx.write(insert=_disjoint(ctx, subs))
    return _OK()


# MAKE EQUIVALENT -------------------------------------------------------------------------------


def make_equivalent_class(ctx: Context) -> Outcome:
    cls = ctx.name(0, "class")
    if ctx.buffered():
        return _OK()
    reference = ctx.reference()
    edges = ctx.session.quads(reference, cls, RDFS_SUBCLASSOF, graph=reference.asserted)
    supers = [q.object for q in edges if isinstance(q.object, NamedNode)]
    if not supers:
        return _OK()
    if len(supers) == 1:
        ctx.write(delete=edges, insert=[ctx.quad(cls, OWL_EQUIVALENT_CLASS, supers[0])])
        return _OK()
    node = _fresh()
    head, cells = _rdf_list(ctx, supers)
    ctx.write(
        delete=edges,
        insert=[
            ctx.quad(cls, OWL_EQUIVALENT_CLASS, node),
            ctx.quad(node, RDF_TYPE, OWL_CLASS),
            ctx.quad(node, OWL_INTERSECTION_OF, head),
            *cells,
        ],
    )
    return _OK()


# REMOVE ----------------------------------------------------------------------------------------


def _axioms_mentioning(ctx: Context, entity: NamedNode) -> list[Quad]:
    """Every asserted triple of an axiom that mentions ``entity``, blank-node structures whole
    (OWLAPI's entity remover drops ``DifferentIndividuals(a, b, entity)`` entirely)."""
    reference = ctx.reference()
    graph = reference.asserted

    def quads(
        s: NamedNode | None = None, p: NamedNode | None = None, o: NamedNode | None = None
    ) -> list[Quad]:
        return ctx.session.quads(reference, s, p, o, graph=graph)

    found = set(quads(entity)) | set(quads(None, entity)) | set(quads(None, None, entity))
    roots: set[NamedNode] = set()
    for quad in list(found):
        for node in (quad.subject, quad.object):
            if is_skolem(node):
                assert isinstance(node, NamedNode)
                roots.add(_structure_root(quads, node))
    for root in roots:
        found |= set(quads(None, None, root))
        todo, seen = [root], {root}
        while todo:
            node = todo.pop()
            for quad in quads(node):
                found.add(quad)
                if is_skolem(quad.object) and quad.object not in seen:
                    assert isinstance(quad.object, NamedNode)
                    seen.add(quad.object)
                    todo.append(quad.object)
    return sorted(found, key=str)


def _structure_root(quads: Callable[..., list[Quad]], node: NamedNode) -> NamedNode:
    seen = {node}
    while True:
        parents = [
            q.subject
            for q in quads(None, None, node)
            if is_skolem(q.subject) and q.subject not in seen
        ]
        if not parents:
            return node
        node = parents[0]  # type: ignore[assignment]
        seen.add(node)


def remove_ind(ctx: Context) -> Outcome:
    ind = ctx.name(0, "individual")
    if ctx.buffered():
        return _OK()
    ctx.write(delete=_axioms_mentioning(ctx, ind))
    return _OK()


def remove_class(ctx: Context) -> Outcome:
    cls = ctx.name(0, "class")
    if ctx.buffered():
        return _OK()
    ctx.write(delete=[ctx.quad(cls, RDFS_SUBCLASSOF, OWL_THING)])
    return _OK()


def remove_ind_class(ctx: Context) -> Outcome:
    ind, cls = ctx.name(0, "individual"), ctx.name(1, "class")
    if ctx.buffered():
        return _OK()
    ctx.write(delete=[ctx.quad(ind, RDF_TYPE, cls)])
    return _OK()


def remove_class_class(ctx: Context) -> Outcome:
    sub, sup = ctx.name(0, "subclass"), ctx.name(1, "superclass")
    if ctx.buffered():
        return _OK()
    ctx.write(delete=[ctx.quad(sub, RDFS_SUBCLASSOF, sup)])
    return _OK()


def remove_dataprop_ind(ctx: Context) -> Outcome:
    prop, ind = ctx.name(0, "data property"), ctx.name(1, "individual")
    value = _typed_value(ctx, 2, 3)
    if value is None:
        return _unsupported(ctx, ctx.args[0], ctx.args[1], "removed from", success=True)
    if ctx.buffered():
        return _OK()
    ctx.write(delete=[ctx.quad(ind, prop, value)])
    return _OK()


def remove_objectprop_ind(ctx: Context) -> Outcome:
    prop, ind = ctx.name(0, "object property"), ctx.name(1, "individual")
    value = ctx.name(2, "value individual")
    if ctx.buffered():
        return _OK()
    ctx.write(delete=[ctx.quad(ind, prop, value)])
    return _OK()


# REPLACE ---------------------------------------------------------------------------------------


def replace_dataprop_ind(ctx: Context) -> Outcome:
    prop, ind = ctx.name(0, "data property"), ctx.name(1, "individual")
    new = _typed_value(ctx, 2, 3)
    ctx.arg(4, "old value")
    if new is None:
        return _unsupported(ctx, ctx.args[0], ctx.args[1], "replaced in", success=False)
    old = to_literal(ctx.args[2], ctx.args[4], field="args[4]")
    if ctx.buffered():
        return _OK()
    ctx.write(
        delete=[ctx.quad(ind, prop, old)],
        insert=[ctx.quad(ind, prop, new), *_declare(ctx, prop, OWL_DATATYPE_PROPERTY)],
    )
    return _OK()


def replace_objectprop_ind(ctx: Context) -> Outcome:
    prop, ind = ctx.name(0, "object property"), ctx.name(1, "individual")
    new, old = ctx.name(2, "new value individual"), ctx.name(3, "old value individual")
    if ctx.buffered():
        return _OK()
    ctx.write(
        delete=[ctx.quad(ind, prop, old)],
        insert=[ctx.quad(ind, prop, new), *_declare(ctx, prop, OWL_OBJECT_PROPERTY)],
    )
    return _OK()


# RENAME ----------------------------------------------------------------------------------------


def rename(ctx: Context) -> Outcome:
    old, new = ctx.name(0, "old name"), ctx.name(1, "new name")
    if ctx.buffered():
        return _OK()
    reference = ctx.reference()
    session = ctx.session
    found = (
        set(session.quads(reference, old))
        | set(session.quads(reference, None, old))
        | set(session.quads(reference, None, None, old))
    )

    def swap(term: object) -> object:
        return new if term == old else term

    renamed = [
        Quad(swap(q.subject), swap(q.predicate), swap(q.object), q.graph_name)  # type: ignore[arg-type]
        for q in found
    ]
    ctx.write(delete=sorted(found, key=str), insert=renamed)
    return _OK()


HANDLERS: dict[str, Callable[[Context], Outcome]] = {
    "ADD_IND_": add_ind,
    "ADD_CLASS_": add_class,
    "ADD_IND_CLASS": add_ind_class,
    "ADD_CLASS_CLASS": add_class_class,
    "ADD_DATAPROP_IND": add_dataprop_ind,
    "ADD_OBJECTPROP_IND": add_objectprop_ind,
    "ADD_CARDINALITY_MIN": add_cardinality_min,
    "ADD_MIN_CARDINALITY": add_cardinality_min,  # the key commands.md documents
    "DISJOINT_IND_": disjoint_ind,
    "DISJOINT_CLASS_": disjoint_class,
    "DISJOINT_IND_CLASS": disjoint_ind_class,
    "DISJOINT_CLASS_CLASS": disjoint_class_class,
    "MAKE_EQUIVALENT_CLASS": make_equivalent_class,
    "REMOVE_IND_": remove_ind,
    "REMOVE_CLASS_": remove_class,
    "REMOVE_IND_CLASS": remove_ind_class,
    "REMOVE_CLASS_CLASS": remove_class_class,
    "REMOVE_DATAPROP_IND": remove_dataprop_ind,
    "REMOVE_OBJECTPROP_IND": remove_objectprop_ind,
    "REPLACE_DATAPROP_IND": replace_dataprop_ind,
    "REPLACE_OBJECTPROP_IND": replace_objectprop_ind,
    "RENAME_IND_": rename,
    "RENAME_CLASS_": rename,
    "RENAME_DATAPROP_": rename,
    "RENAME_OBJECTPROP_": rename,
}
