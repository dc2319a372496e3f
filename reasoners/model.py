"""The in-memory mirror of the scene memory, in parts: the class graph, the score table, the
items, the memory's state and the trash.

The store is the source of truth; :mod:`reasoners.persist` fills a :class:`MemoryModel` from
its triples on open (:meth:`MemoryModel.load`), :mod:`reasoners.index_file` from the index file
(:meth:`MemoryModel.restore`), and the memory rebuilds it from the store after a failed
transaction. Everything else reaches a part directly:

>>> from ontologies.vocab import PLANE, engram
>>> from reasoners.signature import Signature
>>> model = MemoryModel(weights=(0.2, 0.2, 0.3, 0.3))
>>> t = dt.datetime(2025, 1, 1, tzinfo=dt.UTC)
>>> sig = Signature({(engram("sphereIsAboveOf"), PLANE): 1})
>>> record = ClassRecord(engram("Scene-1"), sig, 1, 0, 0.0, t, t)
>>> _ = model.graph.add_class(record)
>>> round(model.scores.zeta(record), 9), model.scores.normalised(record)  # about 1e-13 off
(0.5, 1.0)
"""

import datetime as dt
from collections import Counter
from collections.abc import Iterable
from dataclasses import dataclass, field

from pyoxigraph import NamedNode

from reasoners.class_graph import ClassGraph, Restriction
from reasoners.index import SignatureIndex
from reasoners.item_table import ItemTable
from reasoners.records import ClassRecord, TrashedClass, TrashedItem
from reasoners.score_table import ScoreTable
from reasoners.signature import Key

__all__ = ["Derived", "MemoryModel", "ModelState", "Trash"]

Derived = tuple[dict[Key, list[int]], dict[int, int], list[tuple[tuple[int, int, int], list[int]]]]
"""The index's bitsets (at least n per key, per complexity) and each class's (Z, child sums)."""


@dataclass
class ModelState:
    """What the memory-state individual of the ``memory`` graph holds, and the numbering of
    new classes and items."""

    next_class: int = 1
    next_item: int = 1
    last_sleep_at: dt.datetime | None = None
    updates_since_sleep: int = 0
    sleep_passes: int = 0
    history_epoch: int | None = None
    """The history epoch new class events go to (reasoners.history.current_epoch); None until
    the memory reads it from the store, once per model."""
    has_state: bool = False
    """Whether the ``memory`` graph holds the memory-state individual."""


@dataclass
class Trash:
    """The forgotten classes and items, by IRI, until restored or emptied."""

    classes: dict[NamedNode, TrashedClass] = field(default_factory=dict)
    items: dict[NamedNode, TrashedItem] = field(default_factory=dict)


class MemoryModel:
    """Everything the memory needs to answer without querying the store, in parts: ``graph``
    (the classes and their edges), ``scores`` (their live scores), ``items`` (the experienced
    scenes), ``state`` and ``trash``.

    ``weights`` are (a_d, a_c, a_s, a_r) of the semantic score.
    """

    def __init__(self, weights: tuple[float, float, float, float] = (0.2, 0.2, 0.3, 0.3)) -> None:
        index, classes = SignatureIndex(), dict[NamedNode, ClassRecord]()
        self.items = ItemTable()
        self.scores = ScoreTable(index, classes, weights)
        self.graph = ClassGraph(self.scores, self.items, index, classes)
        self.state = ModelState()
        self.trash = Trash()

    def load(
        self,
        records: Iterable[ClassRecord],
        edges: Iterable[tuple[NamedNode, NamedNode]],
    ) -> None:
        """Bulk-load classes and their stored (child, parent) edges; Z is derived from scratch.

        Indexes the classes in one pass (:meth:`SignatureIndex.add_all`) and fills the score
        rows at once: rebuilding a memory of 100,000 classes from its triples takes seconds,
        not minutes (an index file is read by :meth:`restore`, which re-derives nothing).
        """
        graph, scores = self.graph, self.scores
        records = list(records)
        graph.index.add_all((r.iri, r.signature) for r in records)
        graph.register_all(records)
        classes, parents, children = graph.classes, graph.parents, graph.children
        for child, parent in edges:
            below, above = classes.get(child), classes.get(parent)
            if below is None or above is None or parent in parents[child]:
                continue
            parents[child].add(parent)
            children[parent].add(child)
            below.up.append(above)
            above.fan_in += 1
        ordered = sorted(classes.values(), key=lambda r: -r.signature.complexity)
        own = scores.own
        for record in ordered:  # children (more complex) before parents
            record.z = z = own(record)
            for above in record.up:
                sums = above.sums
                sums[0] += z[0]
                sums[1] += z[1]
                sums[2] += z[2]
        scores.loaded(ordered)

    def restore(
        self,
        records: list[ClassRecord],
        parents: list[set[NamedNode]],
        children: list[set[NamedNode]],
        at_least: dict[Key, list[int]],
        by_complexity: dict[int, int],
        restrictions: Counter[Restriction],
    ) -> None:
        """Take classes as a saved index file holds them (an empty model only): every record
        complete (Z, child sums, parent records, fan-in, written Z), ``parents[k]`` and
        ``children[k]`` the direct edges of ``records[k]``, the index's bitsets for the records
        in their order, and ``restrictions`` what the signatures use. Nothing is re-derived, and
        no table is filled class by class (opening 100,000 classes takes under two seconds).

        Raises ValueError if the model holds classes already.
        """
        graph, scores = self.graph, self.scores
        if graph.classes:
            raise ValueError("restore: the model is not empty")
        nodes = [r.iri for r in records]
        graph.index.restore(
            list(zip(nodes, (r.signature for r in records), strict=True)), at_least, by_complexity
        )
        # filled in place: the score table shares the dictionary
        graph.classes.update(zip(nodes, records, strict=True))
        graph.parents = dict(zip(nodes, parents, strict=True))
        graph.children = dict(zip(nodes, children, strict=True))
        self.items.items_of = {node: set() for node in nodes}
        scores.complexities = Counter(r.signature.complexity for r in records)
        scores.store_counts = Counter(r.store_count for r in records)
        scores.retrieve_counts = Counter(r.retrieve_count for r in records)
        graph.restrictions = restrictions
        scores.loaded(records)

    def derived(self) -> "Derived | None":
        """What :meth:`load` would derive for the graph's classes (in their order), for
        :meth:`restore`: the index's bitsets (squeezed where classes were removed) and each
        class's Z and child sums, all current; None if the index does not hold the classes in
        their order, so that a load re-derives them."""
        graph = self.graph
        self.scores.refresh()
        if graph.index.classes() != list(graph.classes):
            return None
        at_least, by_complexity = graph.index.state()
        scores = [(r.z, list(r.sums)) for r in graph.classes.values()]
        return (at_least, by_complexity, scores)
