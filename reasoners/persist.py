"""How the scene memory is written as triples, and read back into a :class:`MemoryModel`.

Layout (DESIGN.md, "Store layout"):

- ``memory``: each learned class ``C a owl:Class; rdfs:subClassOf engram:Scene;
  owl:equivalentClass ⊓(≥n p.T)`` (an ``owl:intersectionOf`` list of ``owl:Restriction`` with
  ``owl:minQualifiedCardinality`` and ``owl:onClass``, or the single restriction itself), its
  direct ``rdfs:subClassOf`` edges to other learned classes, a label spelling out the
  definition and the short name as ``skos:notation``, and its annotations (complexity,
  storeCount, retrieveCount, rawScore = raw ζ as of the class's last learn, store, retrieval
  or restore, created, lastAccessed, consecutiveWeakCount and pinned when not 0 / false); the
  *score view*: ``scoreTermComplexity``, ``scoreTermStore``, ``scoreTermRetrieve`` (Z_d, Z_s,
  Z_r as xsd:double, exact whenever the store is read:
  :meth:`reasoners.transactions.Transactions.settle_view`) on each class, and ``scoreFactor*``,
  ``maxRawScore`` and ``usesPolicy`` on ``engram:memoryState`` (with the last sleep, the
  updates since, and ``sleepLevels``, the level the last sleep pass gave each live class and
  experienced scene: :func:`write_levels`), from which ``sparql/memory_class_scores.rq`` derives
  every class's live raw and normalised score and level (:func:`write_view`). What the view
  derives is not stored per class (docs/data-model.md). A restriction ``≥n p.T`` is one node
  (:func:`restriction_iri`) shared by every class that uses it, written with the first such
  class and deleted with the last; the export gives each use its own blank node.
- ``episodic``: each experienced scene ``e a engram:ExperiencedScene, C`` with created,
  lastAccessed, complexity, consecutiveWeakCount and pinned when not 0 / false, optional
  ``engram:happenedDuring`` episode, ``engram:hasPrimitive`` links to its primitives, which
  carry their type, id and attributes and the primary relations (the scene's time is the
  primitives' time; the export declares the individuals).
- ``trash``: forgotten classes as ``C rdfs:subClassOf engram:Trash`` with their annotations
  (the consecutive WEAK count that forgot them, and ``sleepLevel`` WEAK),
  ``engram:forgottenAt`` and ``engram:forgottenSignature`` (no definition, so nothing is
  recognised as them), and forgotten experienced scenes with their primitives.
"""

import base64
import datetime as dt
import functools
import hashlib
import re
import uuid
import zlib
from collections import defaultdict
from collections.abc import Iterable, Mapping, Sequence

from pyoxigraph import Literal, NamedNode, Quad

from kg.primitive import Primitive
from kg.scene_triples import write_primitive
from kg.skolem import is_skolem
from kg.store import Store
from kg.transaction import QuadReader, Transaction
from ontologies.vocab import (
    CLASS_SIGNATURE,
    COMPLEXITY,
    CONSECUTIVE_WEAK_COUNT,
    CREATED,
    EPISODIC,
    EXPERIENCED_SCENE,
    FORGOTTEN_AT,
    FORGOTTEN_SIGNATURE,
    HAPPENED_DURING,
    HAS_PRIMITIVE,
    LAST_ACCESSED,
    LAST_SLEEP_AT,
    LEVEL,
    MAX_RAW_SCORE,
    MEMORY,
    MEMORY_STATE,
    MEMORY_STATE_INDIVIDUAL,
    OWL_CLASS,
    OWL_EQUIVALENT_CLASS,
    OWL_INTERSECTION_OF,
    OWL_MIN_QUALIFIED_CARDINALITY,
    OWL_NAMED_INDIVIDUAL,
    OWL_ON_CLASS,
    OWL_ON_PROPERTY,
    OWL_RESTRICTION,
    PINNED,
    RDF_FIRST,
    RDF_NIL,
    RDF_REST,
    RDF_TYPE,
    RDFS_LABEL,
    RDFS_SUBCLASSOF,
    RETRIEVE_COUNT,
    SCENE,
    SCORE,
    SCORE_FACTORS,
    SCORE_TERM_PROPERTIES,
    SCORE_TERMS,
    SKOLEM_PREFIX,
    SKOS_NOTATION,
    SLEEP_LEVELS,
    SLEEP_PASS_COUNT,
    STORE_COUNT,
    TRASH,
    TRASH_CLASS,
    UPDATES_SINCE_SLEEP,
    USES_POLICY,
    XSD_DATETIME,
    engram,
)
from reasoners.encode import Relation
from reasoners.labels import label
from reasoners.model import MemoryModel
from reasoners.records import ClassRecord, ItemRecord, TrashedClass, TrashedItem
from reasoners.score_table import SCALE
from reasoners.signature import Key, Signature

__all__ = [
    "class_iri",
    "item_iri",
    "load_model",
    "set_value",
    "time_literal",
    "write_class",
    "write_edges",
    "write_item",
    "write_levels",
]

Term = NamedNode | Literal
RESTRICTION_PREFIX = SKOLEM_PREFIX + "min-"
_NUMBERED = re.compile(r"-(\d+)$")


def class_iri(number: int) -> NamedNode:
    return engram(f"Scene-{number}")


def item_iri(number: int) -> NamedNode:
    return engram(f"experience-{number}")


def time_literal(value: dt.datetime) -> Literal:
    """An ``xsd:dateTime`` at millisecond precision (what HermiT and the OWL API accept); a time
    with finer digits (written by an older Engram) keeps them, so that it matches its triple."""
    fine = value.microsecond % 1000
    return Literal(
        value.isoformat(timespec="microseconds" if fine else "milliseconds"),
        datatype=XSD_DATETIME,
    )


def parse_time(term: object) -> dt.datetime:
    if not isinstance(term, Literal):
        raise ValueError(f"expected an xsd:dateTime literal, got {term!r}")
    return dt.datetime.fromisoformat(term.value)


def delete_quad(tx: Transaction, quad: Quad, graph: NamedNode) -> None:
    """Delete a stored quad's triple from ``graph`` (Engram stores no RDF-star triples)."""
    tx.delete(quad.subject, quad.predicate, quad.object, graph)  # type: ignore[arg-type]


def insert_quad(tx: Transaction, quad: Quad, graph: NamedNode) -> None:
    """Insert a stored quad's triple into ``graph``."""
    tx.insert(quad.subject, quad.predicate, quad.object, graph)  # type: ignore[arg-type]


def text(term: object) -> str:
    """The lexical value of an IRI or literal."""
    if not isinstance(term, NamedNode | Literal):
        raise TypeError(f"expected an IRI or a literal, got {term!r}")
    return term.value


def set_value(
    tx: Transaction,
    subject: NamedNode,
    prop: NamedNode,
    old: Term | None,
    new: Term,
    graph: NamedNode,
) -> None:
    """Replace one value (``old`` is what the model holds, hence what the store holds)."""
    if old is not None:
        tx.delete(subject, prop, old, graph)
    tx.insert(subject, prop, new, graph)


# Classes -------------------------------------------------------------------------------------


@functools.cache
def restriction_iri(key: Key, n: int) -> NamedNode:
    """The skolem IRI of the restriction ``≥n p.T``: one node per restriction, shared by every
    class that uses it (the export gives each use its own blank node again, as OWL 2 DL wants).
    Kept once computed: a memory uses a few thousand restrictions, and a learn names ~100."""
    digest = hashlib.sha256(f"{key[0].value} {key[1].value} {n}".encode()).hexdigest()[:32]
    return NamedNode(f"{RESTRICTION_PREFIX}{digest}")


def is_restriction(term: object) -> bool:
    """True for a shared restriction node written by :func:`write_class`."""
    return isinstance(term, NamedNode) and term.value.startswith(RESTRICTION_PREFIX)


def _restriction_triples(key: Key, n: int) -> list[tuple[NamedNode, NamedNode, Term]]:
    node = restriction_iri(key, n)
    return [
        (node, RDF_TYPE, OWL_RESTRICTION),
        (node, OWL_ON_PROPERTY, key[0]),
        (node, OWL_ON_CLASS, key[1]),
        (node, OWL_MIN_QUALIFIED_CARDINALITY, Literal(n)),
    ]


def write_restriction(tx: Transaction, key: Key, n: int, graph: NamedNode = MEMORY) -> None:
    for triple in _restriction_triples(key, n):
        tx.insert(*triple, graph)


def delete_restriction(tx: Transaction, key: Key, n: int, graph: NamedNode = MEMORY) -> None:
    for triple in _restriction_triples(key, n):
        tx.delete(*triple, graph)


def write_class(
    tx: Transaction,
    record: ClassRecord,
    graph: NamedNode = MEMORY,
    *,
    stored: set[tuple[Key, int]] | None = None,
) -> None:
    """The definition ``C ≡ ⊓(≥n p.T)``, ``C ⊑ Scene``, a label and every annotation.

    Restriction nodes are shared: those in ``stored`` (the ones the graph already holds) are
    not written again, and the new ones are added to it. Without ``stored``, all are written.
    """
    cls = record.iri
    tx.insert(cls, RDF_TYPE, OWL_CLASS, graph)
    tx.insert(cls, RDFS_SUBCLASSOF, SCENE, graph)
    write_label(tx, record, graph)
    restrictions: list[NamedNode] = []
    for key, n in record.signature.items():
        if stored is None or (key, n) not in stored:
            write_restriction(tx, key, n, graph)
            if stored is not None:
                stored.add((key, n))
        restrictions.append(restriction_iri(key, n))
    if len(restrictions) == 1:  # OWL 2 has no one-operand intersection
        tx.insert(cls, OWL_EQUIVALENT_CLASS, restrictions[0], graph)
    else:
        # the blank nodes of the definition and its list, as the skolem IRIs a transaction
        # would give them, from one random name (a class's ~100 cells took one each)
        definition = NamedNode(SKOLEM_PREFIX + uuid.uuid4().hex)
        cells = [NamedNode(f"{definition.value}-{k}") for k in range(len(restrictions))]
        for k, node in enumerate(restrictions):
            tx.insert(cells[k], RDF_FIRST, node, graph)
            tx.insert(cells[k], RDF_REST, cells[k + 1] if k + 1 < len(cells) else RDF_NIL, graph)
        tx.insert(definition, RDF_TYPE, OWL_CLASS, graph)
        tx.insert(definition, OWL_INTERSECTION_OF, cells[0], graph)
        tx.insert(cls, OWL_EQUIVALENT_CLASS, definition, graph)
    for prop, value in class_annotations(record).items():
        tx.insert(cls, prop, value, graph)


def write_label(tx: Transaction, record: ClassRecord, graph: NamedNode = MEMORY) -> None:
    """The label spelling out the definition, and the short name as ``skos:notation``."""
    cls = record.iri
    tx.insert(cls, RDFS_LABEL, Literal(label(record.signature), language="en"), graph)
    tx.insert(cls, SKOS_NOTATION, Literal(cls.value.rsplit("#", 1)[-1]), graph)


def class_annotations(record: ClassRecord) -> dict[NamedNode, Term]:
    """The annotations of a class; a zero WEAK count and ``pinned`` false are left out (that
    is what their absence means when the class is read back)."""
    values: dict[NamedNode, Term] = {
        CLASS_SIGNATURE: Literal(record.signature.to_json()),
        COMPLEXITY: Literal(record.signature.complexity),
        STORE_COUNT: Literal(record.store_count),
        RETRIEVE_COUNT: Literal(record.retrieve_count),
        SCORE: Literal(record.score),
        CREATED: time_literal(record.created),
        LAST_ACCESSED: time_literal(record.last_accessed),
    }
    if record.weak_count:
        values[CONSECUTIVE_WEAK_COUNT] = Literal(record.weak_count)
    if record.pinned:
        values[PINNED] = Literal(record.pinned)
    return values


def write_edges(
    tx: Transaction,
    added: Iterable[tuple[NamedNode, NamedNode]],
    removed: Iterable[tuple[NamedNode, NamedNode]] = (),
) -> None:
    """Direct subclass edges (child, parent) between learned classes."""
    for child, parent in removed:
        tx.delete(child, RDFS_SUBCLASSOF, parent, MEMORY)
    for child, parent in added:
        tx.insert(child, RDFS_SUBCLASSOF, parent, MEMORY)


def delete_class(tx: Transaction, store: QuadReader, cls: NamedNode) -> list[Quad]:
    """Delete every triple about ``cls`` in ``memory`` (its own definition nodes included, the
    shared restriction nodes not) and return its own quads (annotations, label, edges), for the
    caller to move what it keeps."""
    own = list(store.quads(cls, None, None, MEMORY))
    for quad in own:
        delete_quad(tx, quad, MEMORY)
    stack = [q.object for q in own if is_skolem(q.object) and not is_restriction(q.object)]
    seen: set[NamedNode] = set()
    while stack:
        node = stack.pop()
        if node in seen or not isinstance(node, NamedNode):
            continue
        seen.add(node)
        for quad in store.quads(node, None, None, MEMORY):
            delete_quad(tx, quad, MEMORY)
            if is_skolem(quad.object) and not is_restriction(quad.object):
                stack.append(quad.object)
    for quad in store.quads(None, RDFS_SUBCLASSOF, cls, MEMORY):
        delete_quad(tx, quad, MEMORY)
    return own


# Experienced scenes --------------------------------------------------------------------------


def write_item(
    tx: Transaction,
    record: ItemRecord,
    primitives: Sequence[Primitive],
    relations: Iterable[Relation],
    episode: NamedNode | None,
) -> list[NamedNode]:
    """An experienced scene with its primitives and their primary relations; returns the
    primitives' IRIs.

    Everything the scene was is kept (time, class, episode, every attribute of every primitive,
    every relation the encoder fired), without redundancy: the primitives share the scene's
    time, and ``owl:NamedIndividual`` declarations are left to the export, which adds them.
    """
    item, graph = record.iri, EPISODIC
    observed = time_literal(record.created)
    tx.insert(item, RDF_TYPE, EXPERIENCED_SCENE, graph)
    tx.insert(item, RDF_TYPE, record.cls, graph)
    tx.insert(item, CREATED, observed, graph)
    tx.insert(item, LAST_ACCESSED, time_literal(record.last_accessed), graph)
    tx.insert(item, COMPLEXITY, Literal(record.complexity), graph)
    if episode is not None:
        tx.insert(item, HAPPENED_DURING, episode, graph)
    iris = [NamedNode(f"{item.value}-{k}") for k in range(len(primitives))]
    for iri, primitive in zip(iris, primitives, strict=True):
        tx.insert(item, HAS_PRIMITIVE, iri, graph)
        write_primitive(tx, iri, primitive, graph)
    for relation in relations:
        tx.insert(iris[relation.subject], relation.relation, iris[relation.object], graph)
    return iris


def move(
    tx: Transaction,
    store: QuadReader,
    subjects: Iterable[NamedNode],
    source: NamedNode,
    target: NamedNode,
    *,
    follow: NamedNode | None = None,
) -> None:
    """Move every triple about ``subjects`` (and about the objects they reach by ``follow``)
    from graph ``source`` to graph ``target``."""
    for subject in subjects:
        quads = list(store.quads(subject, None, None, source))
        nested = [q.object for q in quads if follow is not None and q.predicate == follow]
        for quad in quads + [q for n in nested for q in store.quads(n, None, None, source)]:  # type: ignore[arg-type]
            delete_quad(tx, quad, source)
            insert_quad(tx, quad, target)


# Reading back --------------------------------------------------------------------------------


def load_model(
    store: Store, weights: tuple[float, float, float, float] = (0.2, 0.2, 0.3, 0.3)
) -> MemoryModel:
    """Rebuild the in-memory mirror from the ``memory``, ``episodic`` and ``trash`` graphs;
    ``weights`` (a_d, a_c, a_s, a_r) are the policy's semantic-score weights.

    Only what the model holds is read, by the ``memory_load_*`` queries: the experienced
    scenes' primitives and relations, and the trashed scenes' and classes' other values, are not.
    """
    model = MemoryModel(weights=weights)
    nodes = _rows_by_subject(store.select("memory_load_restrictions", g=MEMORY), "restriction")
    restrictions: dict[str, tuple[Key, int]] = {}
    for node, values in nodes.items():
        key = (values[OWL_ON_PROPERTY][0], values[OWL_ON_CLASS][0])
        restrictions[node.value] = (key, int(values[OWL_MIN_QUALIFIED_CARDINALITY][0].value))  # type: ignore[assignment]
        if is_restriction(node):
            model.graph.stored_restrictions.add(restrictions[node.value])
    rows = _rows_by_subject(store.select("memory_load_classes", g=MEMORY), "class")
    definitions: dict[NamedNode, list[str]] = {}
    if any(CLASS_SIGNATURE not in values for values in rows.values()):
        # A class written without its engram:signature: walk the owl:intersectionOf lists.
        definitions = {
            row["class"]: row["restrictions"].value.split()  # type: ignore[misc]
            for row in store.select("memory_load_definitions", g=MEMORY)
        }
    classes: list[ClassRecord] = []
    for subject, values in rows.items():
        if CLASS_SIGNATURE in values:
            signature = Signature.from_json(_one(values, CLASS_SIGNATURE).value)
        elif subject in definitions:
            signature = Signature(dict(restrictions[node] for node in definitions[subject]))
        else:
            raise KeyError(f"learned class {subject} has no owl:equivalentClass definition")
        classes.append(
            ClassRecord(
                iri=subject,
                signature=signature,
                store_count=_int(values, STORE_COUNT),
                retrieve_count=_int(values, RETRIEVE_COUNT),
                score=float(values[SCORE][0].value) if SCORE in values else 0.0,
                created=parse_time(_one(values, CREATED)),
                last_accessed=parse_time(_one(values, LAST_ACCESSED)),
                weak_count=_int(values, CONSECUTIVE_WEAK_COUNT),
                pinned=_bool(values, PINNED),
                level=values[LEVEL][0].value if LEVEL in values else None,  # before sleepLevels
                written_z=_fixed(values),
            )
        )
    edges = [
        (row["child"], NamedNode(parent))
        for row in store.select("memory_load_edges", g=MEMORY)
        for parent in row["parents"].value.split()
    ]
    model.load(sorted(classes, key=lambda r: _number(r.iri)), edges)  # type: ignore[arg-type]
    state: dict[NamedNode, list[Term]] = defaultdict(list)
    for quad in store.quads(MEMORY_STATE_INDIVIDUAL, None, None, MEMORY):
        state[quad.predicate].append(quad.object)  # type: ignore[arg-type]
    model.state.has_state = bool(state)
    if LAST_SLEEP_AT in state:
        model.state.last_sleep_at = parse_time(state[LAST_SLEEP_AT][0])
    model.state.updates_since_sleep = _int(state, UPDATES_SINCE_SLEEP)
    model.state.sleep_passes = _int(state, SLEEP_PASS_COUNT)
    view = (*SCORE_FACTORS, MAX_RAW_SCORE)
    if all(len(state.get(prop, ())) == 1 for prop in view):
        model.scores.written_factors = tuple(float(state[prop][0].value) for prop in view)  # type: ignore[assignment]
    levels = read_levels(state.get(SLEEP_LEVELS, ()))

    items = store.select("memory_load_items", g=EPISODIC)
    for subject, values in _rows_by_subject(items, "item").items():
        cls = next(t for t in values[RDF_TYPE] if t in model.graph.classes)
        model.items.add(
            ItemRecord(
                iri=subject,
                cls=cls,  # type: ignore[arg-type]
                complexity=_int(values, COMPLEXITY),
                created=parse_time(_one(values, CREATED)),
                last_accessed=parse_time(_one(values, LAST_ACCESSED)),
                weak_count=_int(values, CONSECUTIVE_WEAK_COUNT),
                pinned=_bool(values, PINNED),
                level=values[LEVEL][0].value if LEVEL in values else None,  # before sleepLevels
            )
        )
    for iri, level in levels.items():
        record_ = model.graph.classes.get(iri) or model.items.records.get(iri)
        if record_ is not None:
            record_.level = level
    trash = _rows_by_subject(store.select("memory_load_trash", g=TRASH), "subject")
    for subject, values in trash.items():
        if TRASH_CLASS in values[_KIND]:
            model.trash.classes[subject] = TrashedClass(
                subject,
                Signature.from_json(_one(values, FORGOTTEN_SIGNATURE).value),
                parse_time(_one(values, FORGOTTEN_AT)),
            )
        else:
            cls = next(
                t for t in values[RDF_TYPE] if t not in (EXPERIENCED_SCENE, OWL_NAMED_INDIVIDUAL)
            )
            model.trash.items[subject] = TrashedItem(
                subject,
                cls,  # type: ignore[arg-type]
                parse_time(_one(values, FORGOTTEN_AT)),
            )
    model.state.next_class = 1 + max(
        (_number(c) for c in [*model.graph.classes, *model.trash.classes]), default=0
    )
    model.state.next_item = 1 + max(
        (_number(i) for i in [*model.items.records, *model.trash.items]), default=0
    )
    return model


def write_state(tx: Transaction, model: MemoryModel, previous: MemoryModel | None = None) -> None:
    """Replace the memory-state individual's three counters (the score view's values on it
    are :func:`write_view`'s)."""
    node = MEMORY_STATE_INDIVIDUAL
    model.state.has_state = True
    for prop in (UPDATES_SINCE_SLEEP, SLEEP_PASS_COUNT, LAST_SLEEP_AT):
        tx.delete_matching(node, prop, None, graph=MEMORY)
    tx.insert(node, RDF_TYPE, OWL_NAMED_INDIVIDUAL, MEMORY)
    tx.insert(node, RDF_TYPE, MEMORY_STATE, MEMORY)
    tx.insert(node, UPDATES_SINCE_SLEEP, Literal(model.state.updates_since_sleep), MEMORY)
    tx.insert(node, SLEEP_PASS_COUNT, Literal(model.state.sleep_passes), MEMORY)
    if model.state.last_sleep_at is not None:
        tx.insert(node, LAST_SLEEP_AT, time_literal(model.state.last_sleep_at), MEMORY)


def term_literal(z: int) -> Literal:
    """One of Z_d, Z_s, Z_r in fixed point as the view stores it: an xsd:double (exact: SCALE
    is 2**40)."""
    return Literal(z / SCALE)


def levels_literal(model: MemoryModel) -> Literal:
    """The level the last sleep pass gave each live class and experienced scene, as
    :data:`~ontologies.vocab.SLEEP_LEVELS` holds it ("<level> <IRI>" lines, zlib + base64)."""
    lines = [
        f"{record.level} {iri.value}"
        for records in (model.graph.classes, model.items.records)
        for iri, record in records.items()
        if record.level is not None
    ]
    packed = zlib.compress("\n".join(lines).encode(), 1)  # level 1: a pass's time, not bytes
    return Literal(base64.b64encode(packed).decode())


def read_levels(terms: Iterable[Term]) -> dict[NamedNode, str]:
    """The levels a :func:`levels_literal` holds (those of several literals merged; a literal
    that does not decode is left out, and the next sleep pass writes the levels again)."""
    levels: dict[NamedNode, str] = {}
    for term in terms:
        try:
            text = zlib.decompress(base64.b64decode(term.value, validate=True)).decode()
        except (ValueError, zlib.error):
            continue
        for line in text.split("\n") if text else ():
            level, _, iri = line.partition(" ")
            levels[NamedNode(iri)] = level
    return levels


def write_levels(tx: Transaction, model: MemoryModel) -> None:
    """Replace the levels of the last sleep pass on the memory state (:func:`levels_literal`)."""
    tx.delete_matching(MEMORY_STATE_INDIVIDUAL, SLEEP_LEVELS, None, graph=MEMORY)
    tx.insert(MEMORY_STATE_INDIVIDUAL, SLEEP_LEVELS, levels_literal(model), MEMORY)


def write_view(tx: Transaction, model: MemoryModel, policy: NamedNode) -> int:
    """Bring the score view up to date: the Z terms of every class whose Z changed since they
    were written, and the factors and largest raw ζ on the memory state. Returns the number of
    classes rewritten.

    The view is what analysts read (``sparql/memory_class_scores.rq``): raw ζ = f_d·Z_d +
    f_s·Z_s + f_r·Z_r, normalised = ζ / max ζ, the level from the policy's thresholds. A change of
    maximum rewrites the four values on the memory state, not the classes; a change of a class's
    Z rewrites the terms that changed, not the others.
    """
    model.scores.refresh()
    rewritten = 0
    classes = model.graph.classes
    for iri in sorted(model.scores.unwritten, key=_iri_text):
        record = classes.get(iri)
        if record is None or record.written_z == record.z:
            continue
        old, new = record.written_z, record.z
        for x, prop in enumerate(SCORE_TERM_PROPERTIES):  # only the terms that changed
            if old is None:  # none stored (what a damaged view held is deleted when it opens)
                tx.insert(iri, prop, term_literal(new[x]), MEMORY)
            elif old[x] != new[x]:
                set_value(tx, iri, prop, term_literal(old[x]), term_literal(new[x]), MEMORY)
        record.written_z = new
        rewritten += 1
    model.scores.unwritten.clear()
    node = MEMORY_STATE_INDIVIDUAL
    factors = (*model.scores.coefficients(), model.scores.max_score)
    if factors != model.scores.written_factors and (
        model.graph.classes or model.scores.written_factors is not None
    ):
        old_factors = model.scores.written_factors
        if old_factors is None:
            tx.insert(node, RDF_TYPE, OWL_NAMED_INDIVIDUAL, MEMORY)
            tx.insert(node, RDF_TYPE, MEMORY_STATE, MEMORY)
            tx.delete_matching(node, USES_POLICY, None, graph=MEMORY)
            tx.insert(node, USES_POLICY, policy, MEMORY)
        for x, prop in enumerate((*SCORE_FACTORS, MAX_RAW_SCORE)):
            if old_factors is None:
                tx.delete_matching(node, prop, None, graph=MEMORY)
                tx.insert(node, prop, Literal(factors[x]), MEMORY)
            elif old_factors[x] != factors[x]:
                set_value(tx, node, prop, Literal(old_factors[x]), Literal(factors[x]), MEMORY)
        model.scores.written_factors = factors
    return rewritten


def _iri_text(iri: NamedNode) -> str:
    return iri.value


VIEW_PREDICATES = frozenset({*SCORE_TERM_PROPERTIES, SCORE_TERMS})
"""The score view's triples on a class (not moved to the trash with it)."""


_KIND = engram("_kind")
"""Not stored: the key under which :func:`_rows_by_subject` keeps the trash query's ``?kind``."""

_COLUMNS: dict[str, NamedNode] = {
    "property": OWL_ON_PROPERTY,
    "onClass": OWL_ON_CLASS,
    "n": OWL_MIN_QUALIFIED_CARDINALITY,
    "storeCount": STORE_COUNT,
    "retrieveCount": RETRIEVE_COUNT,
    "score": SCORE,
    "created": CREATED,
    "lastAccessed": LAST_ACCESSED,
    "weakCount": CONSECUTIVE_WEAK_COUNT,
    "pinned": PINNED,
    "level": LEVEL,
    "type": RDF_TYPE,
    "complexity": COMPLEXITY,
    "signature": CLASS_SIGNATURE,
    "forgottenSignature": FORGOTTEN_SIGNATURE,
    "forgottenAt": FORGOTTEN_AT,
    "kind": _KIND,
    "zd": SCORE_TERM_PROPERTIES[0],
    "zs": SCORE_TERM_PROPERTIES[1],
    "zr": SCORE_TERM_PROPERTIES[2],
}
"""The ``memory_load_*`` query columns, as the properties whose values they hold."""


def _rows_by_subject(
    rows: Iterable[Mapping[str, Term]], subject: str
) -> dict[NamedNode, dict[NamedNode, list[Term]]]:
    """The values of each ``subject`` in query rows, per property (each distinct value once, in
    the order of the rows), as the loaders read them."""
    out: dict[NamedNode, dict[NamedNode, list[Term]]] = {}
    for row in rows:
        values = out.setdefault(row[subject], defaultdict(list))  # type: ignore[arg-type]
        for column, term in row.items():
            if column != subject and term not in (seen := values[_COLUMNS[column]]):
                seen.append(term)
    return out


def _one(values: dict[NamedNode, list[Term]], prop: NamedNode) -> Literal:
    term = values[prop][0]
    assert isinstance(term, Literal)
    return term


def _fixed(values: dict[NamedNode, list[Term]]) -> tuple[int, int, int] | None:
    """The Z terms a class's view holds, in fixed point; None unless it holds exactly one each
    (the view is then rewritten whole)."""
    found: list[Sequence[Term]] = [values.get(prop, []) for prop in SCORE_TERM_PROPERTIES]
    if any(len(terms) != 1 for terms in found):
        return None
    try:
        z = [round(float(terms[0].value) * SCALE) for terms in found]
    except ValueError:  # damaged by hand
        return None
    return (z[0], z[1], z[2])


def _int(values: dict[NamedNode, list[Term]], prop: NamedNode) -> int:
    return int(values[prop][0].value) if prop in values else 0


def _bool(values: dict[NamedNode, list[Term]], prop: NamedNode) -> bool:
    return prop in values and values[prop][0].value == "true"


def _number(iri: NamedNode) -> int:
    match = _NUMBERED.search(iri.value)
    return int(match.group(1)) if match else 0
