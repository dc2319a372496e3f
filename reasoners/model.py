"""The in-memory mirror of the scene memory: records, direct subclass edges, maxima.

The store is the source of truth; :mod:`reasoners.persist` fills a :class:`MemoryModel` from
its triples on open, and the memory rebuilds it from the store after a failed transaction.
"""

import datetime as dt
import heapq
import itertools
from collections import Counter
from collections.abc import Iterator
from dataclasses import dataclass, field

from pyoxigraph import NamedNode

from reasoners.index import SignatureIndex
from reasoners.signature import Signature

__all__ = ["ClassRecord", "ItemRecord", "MemoryModel", "TrashedClass", "TrashedItem"]


@dataclass
class ClassRecord:
    """A learned scene class: its signature and the raw terms of its score."""

    iri: NamedNode
    signature: Signature
    store_count: int
    retrieve_count: int
    score: float
    created: dt.datetime
    last_accessed: dt.datetime
    weak_count: int = 0
    pinned: bool = False
    level: str | None = None


@dataclass
class ItemRecord:
    """An experienced scene (episodic item)."""

    iri: NamedNode
    cls: NamedNode
    complexity: int
    created: dt.datetime
    last_accessed: dt.datetime
    weak_count: int = 0
    pinned: bool = False
    level: str | None = None


@dataclass
class TrashedClass:
    iri: NamedNode
    signature: Signature
    forgotten_at: dt.datetime


@dataclass
class TrashedItem:
    iri: NamedNode
    cls: NamedNode
    forgotten_at: dt.datetime


@dataclass
class MemoryModel:
    """Everything the memory needs to answer without querying the store."""

    index: SignatureIndex = field(default_factory=SignatureIndex)
    classes: dict[NamedNode, ClassRecord] = field(default_factory=dict)
    parents: dict[NamedNode, set[NamedNode]] = field(default_factory=dict)
    children: dict[NamedNode, set[NamedNode]] = field(default_factory=dict)
    items: dict[NamedNode, ItemRecord] = field(default_factory=dict)
    items_of: dict[NamedNode, set[NamedNode]] = field(default_factory=dict)
    trashed_classes: dict[NamedNode, TrashedClass] = field(default_factory=dict)
    trashed_items: dict[NamedNode, TrashedItem] = field(default_factory=dict)
    complexities: Counter[int] = field(default_factory=Counter)
    item_complexities: Counter[int] = field(default_factory=Counter)
    store_counts: Counter[int] = field(default_factory=Counter)
    retrieve_counts: Counter[int] = field(default_factory=Counter)
    next_class: int = 1
    next_item: int = 1
    last_sleep_at: dt.datetime | None = None
    updates_since_sleep: int = 0
    sleep_passes: int = 0
    _heap: list[tuple[float, int, NamedNode]] = field(default_factory=list)
    _tick: Iterator[int] = field(default_factory=itertools.count)

    # Maxima ------------------------------------------------------------------------------------

    @property
    def max_complexity(self) -> int:
        return max(self.complexities, default=0)

    @property
    def max_item_complexity(self) -> int:
        return max(self.item_complexities, default=0)

    @property
    def max_store(self) -> int:
        return max(self.store_counts, default=0)

    @property
    def max_retrieve(self) -> int:
        return max(self.retrieve_counts, default=0)

    @property
    def max_score(self) -> float:
        """The largest stored ζ among live classes (a max-heap with lazy deletion)."""
        heap = self._heap
        while heap:
            negative, _, cls = heap[0]
            record = self.classes.get(cls)
            if record is not None and record.score == -negative:
                return -negative
            heapq.heappop(heap)
        return 0.0

    def set_score(self, record: ClassRecord, score: float) -> None:
        record.score = score
        heapq.heappush(self._heap, (-score, next(self._tick), record.iri))

    def rebuild_heap(self) -> None:
        self._heap = [(-r.score, next(self._tick), r.iri) for r in self.classes.values()]
        heapq.heapify(self._heap)

    def normalised(self, record: ClassRecord) -> float:
        top = self.max_score
        return record.score / top if top > 0 else 0.0

    def set_counts(self, record: ClassRecord, *, store: int, retrieve: int) -> None:
        _move(self.store_counts, record.store_count, store)
        _move(self.retrieve_counts, record.retrieve_count, retrieve)
        record.store_count, record.retrieve_count = store, retrieve

    # Classes and edges -------------------------------------------------------------------------

    def add_class(
        self, record: ClassRecord
    ) -> tuple[set[NamedNode], set[NamedNode], set[tuple[NamedNode, NamedNode]]]:
        """Index a class and link it into the transitively reduced graph.

        Returns (direct parents, direct children, removed (child, parent) edges): the edges
        between those parents and children now pass through the new class.
        """
        cls = record.iri
        ancestors = set(self.index.recognised(record.signature))
        descendants = set(self.index.dominating(record.signature))
        parents = {p for p in ancestors if self.children[p].isdisjoint(ancestors)}
        children = {c for c in descendants if self.parents[c].isdisjoint(descendants)}
        removed: set[tuple[NamedNode, NamedNode]] = set()
        for p in parents:
            for c in children & self.children[p]:
                self.children[p].discard(c)
                self.parents[c].discard(p)
                removed.add((c, p))
        self.index.add(cls, record.signature)
        self.classes[cls] = record
        self.parents[cls] = set(parents)
        self.children[cls] = set(children)
        for p in parents:
            self.children[p].add(cls)
        for c in children:
            self.parents[c].add(cls)
        self.items_of.setdefault(cls, set())
        self.complexities[record.signature.complexity] += 1
        self.store_counts[record.store_count] += 1
        self.retrieve_counts[record.retrieve_count] += 1
        self.set_score(record, record.score)
        return parents, children, removed

    def remove_class(self, cls: NamedNode) -> set[tuple[NamedNode, NamedNode]]:
        """Unlink a class; returns the (child, parent) edges that must now be added so the graph
        stays the transitive reduction of signature dominance."""
        record = self.classes.pop(cls)
        self.index.remove(cls)
        parents, children = self.parents.pop(cls), self.children.pop(cls)
        for p in parents:
            self.children[p].discard(cls)
        for c in children:
            self.parents[c].discard(cls)
        added: set[tuple[NamedNode, NamedNode]] = set()
        for c in children:
            for p in parents:
                # p covers c unless another parent of c lies between them.
                between = any(
                    q != p and self.classes[q].signature.satisfies(self.classes[p].signature)
                    for q in self.parents[c]
                )
                if not between:
                    self.parents[c].add(p)
                    self.children[p].add(c)
                    added.add((c, p))
        _move(self.complexities, record.signature.complexity, None)
        _move(self.store_counts, record.store_count, None)
        _move(self.retrieve_counts, record.retrieve_count, None)
        self.items_of.pop(cls, None)
        return added

    def ancestors(self, cls: NamedNode) -> set[NamedNode]:
        """Every class above ``cls`` (its branch up to the roots), without ``cls``."""
        seen: set[NamedNode] = set()
        stack = list(self.parents[cls])
        while stack:
            node = stack.pop()
            if node not in seen:
                seen.add(node)
                stack.extend(self.parents[node])
        return seen

    # Items -------------------------------------------------------------------------------------

    def add_item(self, record: ItemRecord) -> None:
        self.items[record.iri] = record
        self.items_of.setdefault(record.cls, set()).add(record.iri)
        self.item_complexities[record.complexity] += 1

    def remove_item(self, item: NamedNode) -> ItemRecord:
        record = self.items.pop(item)
        self.items_of.get(record.cls, set()).discard(item)
        _move(self.item_complexities, record.complexity, None)
        return record


def _move(counter: Counter[int], old: int | None, new: int | None) -> None:
    if old is not None:
        counter[old] -= 1
        if counter[old] <= 0:
            del counter[old]
    if new is not None:
        counter[new] += 1
