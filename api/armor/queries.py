"""Every QUERY variant, with results written exactly as ARMOR writes them.

Results are sets in ARMOR (Java ``HashSet``); here they come sorted, which is one of the orders
ARMOR could give. ``QUERY SPARQL`` runs over the reference's asserted and inferred graphs.
"""

import re
import time
from collections.abc import Callable

from pyoxigraph import Literal, NamedNode, QueryResultsFormat, QuerySolutions, parse_query_results

from api.armor.context import Context, Outcome
from api.armor.errors import InvalidArgumentsError, SparqlError
from api.armor.names import is_true, jena_string, local_name, styled
from api.armor.references import Reference
from api.protocol import QueryItem
from kg.errors import QueryError, QueryTimeoutError
from kg.literals import from_store
from kg.sandbox import QueryForm
from kg.sparql_text import nesting_depth
from ontologies.vocab import (
    OWL_EQUIVALENT_CLASS,
    OWL_INTERSECTION_OF,
    OWL_NAMED_INDIVIDUAL,
    OWL_NOTHING,
    OWL_NS,
    OWL_ON_CLASS,
    OWL_ON_PROPERTY,
    OWL_THING,
    RDF_FIRST,
    RDF_REST,
    RDF_TYPE,
    RDFS_SUBCLASSOF,
    SKOLEM_PREFIX,
)

__all__ = ["HANDLERS"]

_SKOLEM = Literal(SKOLEM_PREFIX)


def _strings(ctx: Context, terms: list[NamedNode | Literal]) -> list[str]:
    return sorted({styled(term, ctx.style) for term in terms})


def _class_bindings(cls: NamedNode) -> dict[str, NamedNode | Literal]:
    """``class`` is a Python keyword, so it is bound through a dict."""
    return {"class": cls, "skolem": _SKOLEM}


def _column(rows: list[dict[str, NamedNode | Literal]], name: str) -> list[NamedNode | Literal]:
    return [row[name] for row in rows if name in row]


_NOT_CLASSES = frozenset((OWL_THING, OWL_NAMED_INDIVIDUAL))


def _classes_of(ctx: Context, ind: NamedNode) -> list[NamedNode]:
    """Every named class of ``ind`` with all its ancestors, without owl:Thing.

    The answer of ``sparql/armor_ind_classes.rq`` (``?ind rdf:type ?type . ?type
    rdfs:subClassOf* ?class``, distinct IRIs, neither skolem IRIs nor owl:Thing or
    owl:NamedIndividual) read as triple patterns: a SPARQL query costs about twice the
    patterns, and QUERY IND is one of the directives clients send most. The patterns go through
    the session, so they read both graphs of the reference and the list's own pending writes,
    as the query does. The traversal passes through class expressions (skolem IRIs) and stops
    at literals, which cannot be subjects; the classes come in the order they are reached.
    """
    reference = ctx.reference()
    session = ctx.session
    todo = list(dict.fromkeys(quad.object for quad in session.quads(reference, ind, RDF_TYPE)))
    seen = set(todo)
    classes = []
    while todo:
        node = todo.pop()
        if not isinstance(node, NamedNode):
            continue
        if node not in _NOT_CLASSES and not node.value.startswith(SKOLEM_PREFIX):
            classes.append(node)
        for quad in session.quads(reference, node, RDFS_SUBCLASSOF):
            if quad.object not in seen:
                seen.add(quad.object)
                todo.append(quad.object)
    return classes


def query_ind(ctx: Context) -> Outcome:
    """The classes of an individual; ``success=false`` with code 0 if it has none (ARMOR)."""
    classes: list[NamedNode | Literal] = list(_classes_of(ctx, ctx.name(0, "individual")))
    if not classes:
        return Outcome(success=False)
    return Outcome(queried_objects=_strings(ctx, classes))


def query_ind_class(ctx: Context) -> Outcome:
    cls = ctx.name(0, "class")
    rows = ctx.session.select(ctx.reference(), "armor_class_instances", **_class_bindings(cls))
    return Outcome(queried_objects=_strings(ctx, _column(rows, "ind")))


def _values(ctx: Context, *, literal: bool) -> Outcome:
    prop = ctx.name(0, "data property" if literal else "object property")
    ind = ctx.name(1, "individual")
    rows = ctx.session.select(ctx.reference(), "armor_property_values", ind=ind, prop=prop)
    values = [
        v
        for v in _column(rows, "value")
        if isinstance(v, Literal) == literal and not v.value.startswith(SKOLEM_PREFIX)
    ]
    return Outcome(queried_objects=_strings(ctx, values))


def query_dataprop_ind(ctx: Context) -> Outcome:
    return _values(ctx, literal=True)


def query_objectprop_ind(ctx: Context) -> Outcome:
    return _values(ctx, literal=False)


def query_class_ind(ctx: Context) -> Outcome:
    """All classes of an individual, or with ``args[1] == "true"`` one leaf class as a short name.

    ARMOR requires ``args[1]``; Engram defaults it to false, as ARMOR's documentation says.
    """
    ind = ctx.name(0, "individual")
    bottom = is_true(ctx.args[1]) if len(ctx.args) > 1 else False
    classes = _classes_of(ctx, ind)
    if not bottom:
        return Outcome(queried_objects=_strings(ctx, list(classes)))
    reference = ctx.reference()
    leaves = [
        c
        for c in classes
        if not any(
            other != c
            and ctx.session.quads(reference, other, RDFS_SUBCLASSOF, c)
            and not ctx.session.quads(reference, c, RDFS_SUBCLASSOF, other)
            for other in classes
        )
    ]
    leaf = sorted(leaves, key=lambda c: c.value)[:1]
    return Outcome(queried_objects=[local_name(c.value) for c in leaf])


def query_class_class(ctx: Context) -> Outcome:
    """Every subclass, direct or not; owl:Nothing included, as the OWLAPI reasoners give it."""
    cls = ctx.name(0, "class")
    rows = ctx.session.select(ctx.reference(), "armor_subclasses", **_class_bindings(cls))
    subs = _column(rows, "sub")
    if cls != OWL_NOTHING:
        subs.append(OWL_NOTHING)
    return Outcome(queried_objects=_strings(ctx, subs))


def _properties(ctx: Context, *, literal: bool) -> Outcome:
    ind = ctx.name(0, "individual")
    rows = ctx.session.select(ctx.reference(), "armor_ind_properties", ind=ind, skolem=_SKOLEM)
    props = [
        row["prop"]
        for row in rows
        if "prop" in row and "literal" in row and is_true(row["literal"].value) == literal
    ]
    return Outcome(queried_objects=_strings(ctx, props))


def query_ind_dataprop(ctx: Context) -> Outcome:
    return _properties(ctx, literal=True)


def query_ind_objectprop(ctx: Context) -> Outcome:
    return _properties(ctx, literal=False)


# QUERY CLASS RESTRICTIONS ----------------------------------------------------------------------

_RESTRICTION_KINDS = {
    "someValuesFrom": "SOME",
    "allValuesFrom": "ONLY",
    "hasValue": "VALUE",
    "minQualifiedCardinality": "MIN",
    "maxQualifiedCardinality": "MAX",
    "qualifiedCardinality": "EXACT",
    "minCardinality": "MIN",
    "maxCardinality": "MAX",
    "cardinality": "EXACT",
}


def query_class_restrictions(ctx: Context) -> Outcome:
    """One string per superclass or equivalent-class axiom made of restrictions, written as
    AMOR's ``SemanticRestriction`` set: ``[SOME : Class_4 -> OProperty_1(Class_3), …]``."""
    cls = ctx.name(0, "class")
    reference = ctx.reference()
    strings = []
    for predicate in (OWL_EQUIVALENT_CLASS, RDFS_SUBCLASSOF):
        for quad in ctx.session.quads(reference, cls, predicate, graph=reference.asserted):
            if not isinstance(quad.object, NamedNode) or not _text(quad.object).startswith(
                SKOLEM_PREFIX
            ):
                continue
            parts = _restrictions(ctx, reference, cls, quad.object)
            if parts:
                strings.append("[" + ", ".join(parts) + "]")
    return Outcome(queried_objects=sorted(set(strings)))


def _text(term: object) -> str:
    """The IRI or lexical value of a term."""
    return term.value if isinstance(term, NamedNode | Literal) else str(term)


def _restrictions(ctx: Context, reference: Reference, cls: NamedNode, node: NamedNode) -> list[str]:
    session = ctx.session
    members = [node]
    for quad in session.quads(reference, node, OWL_INTERSECTION_OF):
        members = _list_items(ctx, reference, quad.object)  # type: ignore[arg-type]
    parts = []
    for member in members:
        props = session.quads(reference, member, OWL_ON_PROPERTY)
        if not props:
            continue
        prop = local_name(_text(props[0].object))
        for quad in session.quads(reference, member):
            name = quad.predicate.value.removeprefix(OWL_NS)
            kind = _RESTRICTION_KINDS.get(name)
            if kind is None or not quad.predicate.value.startswith(OWL_NS):
                continue
            if kind in ("MIN", "MAX", "EXACT"):
                on = session.quads(reference, member, OWL_ON_CLASS)
                target = local_name(_text(on[0].object)) if on else "Thing"
                parts.append(
                    f"{kind} : {local_name(cls.value)} -> {prop} {_text(quad.object)}({target})"
                )
            else:
                parts.append(
                    f"{kind} : {local_name(cls.value)} -> {prop}({local_name(_text(quad.object))})"
                )
    return sorted(parts)


def _list_items(ctx: Context, reference: Reference, head: NamedNode) -> list[NamedNode]:
    items, seen = [], set()
    while head.value.startswith(SKOLEM_PREFIX) and head not in seen:
        seen.add(head)
        first = ctx.session.quads(reference, head, RDF_FIRST)
        rest = ctx.session.quads(reference, head, RDF_REST)
        items += [q.object for q in first if isinstance(q.object, NamedNode)]
        if not rest or not isinstance(rest[0].object, NamedNode):
            break
        head = rest[0].object
    return items


# QUERY SPARQL ----------------------------------------------------------------------------------


def _sparql_text(ctx: Context) -> tuple[str, float | None]:
    """ARMOR's argument forms: [q], [q, timeout_ms], [prefix, select, where(, timeout_ms)]."""
    args = ctx.args
    if len(args) not in (1, 2, 3, 4):
        raise InvalidArgumentsError(
            f"args: got {len(args)} args, expected [query], [query, timeout_ms], "
            "[prefix, select, where] or [prefix, select, where, timeout_ms]"
        )
    text = args[0] if len(args) <= 2 else "".join(args[:3])
    timeout_s = None
    if len(args) in (2, 4):
        raw = args[-1]
        if not _JAVA_INTEGER.fullmatch(raw):
            raise InvalidArgumentsError(
                f"args[{len(args) - 1}]: got {raw!r}, expected a timeout in milliseconds "
                "(an integer in ASCII digits)"
            )
        timeout_s = int(raw) / 1000
        if timeout_s <= 0:
            timeout_s = None  # Jena: a non-positive timeout means none
    return text, timeout_s


_JAVA_INTEGER = re.compile(r"[+-]?[0-9]+")
_NOT_SELECT = "args: QUERY SPARQL takes a SELECT query (ARMOR runs only SELECT)"
_IN_PROCESS_MAX_DEPTH = 128
"""Nesting levels allowed when no sandbox runs the query (Oxigraph's parser overflows later)."""
_JSON = "application/sparql-results+json"
_SENT_BYTES = 4 * 1024 * 1024
"""A committed reference up to this size (N-Triples) is sent to the worker rather than snapshot."""


def _in_sandbox(ctx: Context, text: str, timeout_s: float | None) -> QuerySolutions:
    """Run ``text`` in the sandbox's worker over the reference as this list sees it."""
    assert ctx.sandbox is not None
    reference = ctx.reference()
    view = ctx.session.view_store(reference)
    graphs = [graph.value for graph in reference.graphs]
    data = None
    if view is not ctx.session.store or not ctx.sandbox.snapshot_is_current():
        # the list's own view, or a reference small enough to send rather than snapshot
        data = {g.value: view.graph_ntriples(g) for g in reference.graphs}
        if view is ctx.session.store and sum(map(len, data.values())) > _SENT_BYTES:
            data = None
    try:
        answer = ctx.sandbox.run(
            text,
            media_types={QueryForm.SOLUTIONS: _JSON},
            default_graphs=graphs,
            named_graphs=graphs,
            graph_data=data,
            timeout_s=timeout_s,
        )
    except QueryTimeoutError as error:
        raise SparqlError(f"args: {error}", timeout=True) from None
    except QueryError as error:
        raise SparqlError(f"args: the SPARQL query was refused: {error}") from None
    if answer.media_type is None:
        raise SparqlError(_NOT_SELECT)
    solutions = parse_query_results(answer.body, format=QueryResultsFormat.JSON)
    assert isinstance(solutions, QuerySolutions)
    return solutions


def _in_process(ctx: Context, text: str) -> QuerySolutions:
    depth = nesting_depth(text)
    if depth > _IN_PROCESS_MAX_DEPTH:
        raise SparqlError(
            f"args: the query nests {depth} levels of braces, parentheses or brackets; "
            f"at most {_IN_PROCESS_MAX_DEPTH} are allowed"
        )
    result = ctx.session.query(ctx.reference(), text)
    if not isinstance(result, QuerySolutions):
        raise SparqlError(_NOT_SELECT)
    return result


def _solutions(ctx: Context) -> list[list[tuple[str, NamedNode | Literal]]]:
    text, timeout_s = _sparql_text(ctx)
    try:
        return _rows(ctx, text, timeout_s)
    except RuntimeError as error:  # Oxigraph's word for an unknown function and the like
        raise SparqlError(f"args: the query cannot be evaluated: {error}") from None


def _rows(
    ctx: Context, text: str, timeout_s: float | None
) -> list[list[tuple[str, NamedNode | Literal]]]:
    if ctx.sandbox is not None:
        result = _in_sandbox(ctx, text, timeout_s)
    else:
        result = _in_process(ctx, text)
    names = [variable.value for variable in result.variables]
    deadline = None if timeout_s is None else time.monotonic() + timeout_s
    rows = []
    for solution in result:
        if deadline is not None and time.monotonic() > deadline:
            raise SparqlError(
                f"args: the query ran past its timeout of {int(timeout_s * 1000)} ms",  # type: ignore[operator]
                timeout=True,
            )
        rows.append(
            [(n, from_store(t)) for n in names if isinstance(t := solution[n], NamedNode | Literal)]
        )
    return rows


def _sparql_value(ctx: Context, term: NamedNode | Literal) -> str:
    if ctx.style == "armor":
        return jena_string(term)
    return styled(term, ctx.style)


def query_sparql(ctx: Context) -> Outcome:
    """One string: Java's ``List<Map>.toString()`` with every bracket removed."""
    rows = _solutions(ctx)
    text = ", ".join(
        "{" + ", ".join(f"{name}={_sparql_value(ctx, term)}" for name, term in row) + "}"
        for row in rows
    )
    return Outcome(queried_objects=[text.replace("[", "").replace("]", "")])


def query_sparql_formatted(ctx: Context) -> Outcome:
    """A flat list of ``{key, value}`` items over all solutions, in order."""
    items = [
        QueryItem(key=name, value=_sparql_value(ctx, term))
        for row in _solutions(ctx)
        for name, term in row
    ]
    return Outcome(sparql_queried_objects=items)


HANDLERS: dict[str, Callable[[Context], Outcome]] = {
    "QUERY_IND_": query_ind,
    "QUERY_IND_CLASS": query_ind_class,
    "QUERY_DATAPROP_IND": query_dataprop_ind,
    "QUERY_OBJECTPROP_IND": query_objectprop_ind,
    "QUERY_CLASS_IND": query_class_ind,
    "QUERY_CLASS_CLASS": query_class_class,
    "QUERY_CLASS_RESTRICTIONS": query_class_restrictions,
    "QUERY_IND_DATAPROP": query_ind_dataprop,
    "QUERY_IND_OBJECTPROP": query_ind_objectprop,
    "QUERY_SPARQL_": query_sparql,
    "QUERY_SPARQL_FORMATTED": query_sparql_formatted,
}
