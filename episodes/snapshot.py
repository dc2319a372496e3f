"""The scene memory's state at an episode's begin and end.

The scene memory (``reasoners/``) writes learned classes with their ``engram:score`` into the
``memory`` graph and experienced scenes into the ``episodic`` graph; :func:`read_memory_state`
only reads them with SPARQL, so the two packages share the graph, not code. The stored score of
a class is the one its last update or the last sleep pass consolidated; a process that holds the
live scene memory passes a :data:`MemoryState` of its own that ranks by the live scores (the
server does, see ``api.main``).
"""

from collections.abc import Callable

from pyoxigraph import Literal, NamedNode

from episodes import _rdf
from episodes.model import ClassEntry, MemorySnapshot
from kg import Store, Transaction
from ontologies.vocab import (
    ENTRY_CLASS,
    ENTRY_RANK,
    ENTRY_SCORE,
    EPISODES,
    EPISODIC_ITEM_COUNT,
    HAS_CLASS_ENTRY,
    LEARNED_CLASS_COUNT,
    MEMORY_SNAPSHOT,
    RDF_TYPE,
    SNAPSHOT_CLASS_ENTRY,
)

__all__ = ["MemoryState", "load_snapshot", "read_memory_state", "write_snapshot"]

MemoryState = Callable[[Store], MemorySnapshot]
"""How the scene memory's state is read when an episode begins or ends."""


def read_memory_state(store: Store) -> MemorySnapshot:
    """Counts of learned classes and episodic items, and the ten best classes by stored score."""
    counts = store.select("episodes_memory_counts")
    row = counts[0] if counts else {}
    best = tuple(
        ClassEntry(cls=_rdf.text(r, "cls"), score=_rdf.number(r, "score"), rank=rank)
        for rank, r in enumerate(store.select("episodes_best_classes"), start=1)
    )
    return MemorySnapshot(
        learned_classes=_rdf.integer(row, "classes") if "classes" in row else 0,
        episodic_items=_rdf.integer(row, "items") if "items" in row else 0,
        best_classes=best,
    )


def write_snapshot(tx: Transaction, node: NamedNode, snapshot: MemorySnapshot) -> None:
    """Record ``snapshot`` as the node ``node`` (entries at ``<node>/<rank>``)."""
    tx.insert(node, RDF_TYPE, MEMORY_SNAPSHOT, EPISODES)
    tx.insert(node, LEARNED_CLASS_COUNT, Literal(snapshot.learned_classes), EPISODES)
    tx.insert(node, EPISODIC_ITEM_COUNT, Literal(snapshot.episodic_items), EPISODES)
    for entry in snapshot.best_classes:
        entry_node = NamedNode(f"{node.value}/{entry.rank}")
        tx.insert(node, HAS_CLASS_ENTRY, entry_node, EPISODES)
        tx.insert(entry_node, RDF_TYPE, SNAPSHOT_CLASS_ENTRY, EPISODES)
        tx.insert(entry_node, ENTRY_CLASS, NamedNode(entry.cls), EPISODES)
        tx.insert(entry_node, ENTRY_SCORE, Literal(float(entry.score)), EPISODES)
        tx.insert(entry_node, ENTRY_RANK, Literal(entry.rank), EPISODES)


def load_snapshot(store: Store, node: NamedNode) -> MemorySnapshot | None:
    """The snapshot stored as ``node``, or ``None`` if there is none."""
    rows = store.select("episodes_snapshot", snapshot=node)
    if not rows:
        return None
    entries = tuple(
        ClassEntry(
            cls=_rdf.text(r, "cls"), score=_rdf.number(r, "score"), rank=_rdf.integer(r, "rank")
        )
        for r in rows
        if "cls" in r
    )
    return MemorySnapshot(
        learned_classes=_rdf.integer(rows[0], "classes"),
        episodic_items=_rdf.integer(rows[0], "items"),
        best_classes=entries,
    )
