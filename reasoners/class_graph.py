"""The learned classes and the transitively reduced graph of signature dominance between them.

A class is the parent of another when its signature is satisfied by the other's (it is more
general); the graph keeps the direct edges only. :meth:`ClassGraph.add_class` indexes a class
and links it in, re-linking the edges that now pass through it; :meth:`ClassGraph.remove_class`
unlinks one and links its children to its parents where nothing lies between. The graph tells
the score table every change that moves a score (it calls the table, never the other way), and
keeps the item table's per-class sets in step with the classes.
"""

import itertools
from collections import Counter
from collections.abc import Iterable
from dataclasses import dataclass, field

from pyoxigraph import NamedNode

from reasoners.index import SignatureIndex
from reasoners.item_table import ItemTable
from reasoners.records import ClassRecord
from reasoners.score_table import ScoreTable, move_count
from reasoners.signature import Key

__all__ = ["ClassGraph", "Restriction"]

Restriction = tuple[Key, int]
"""One restriction ``≥n p.T`` as ((p, T), n)."""


@dataclass
class ClassGraph:
    """The classes by IRI, their signature index and direct edges, and the restriction nodes
    their signatures use. ``index`` and ``classes`` are shared with ``scores``, which reads
    them."""

    scores: ScoreTable = field(repr=False, compare=False)
    items: ItemTable = field(repr=False, compare=False)
    index: SignatureIndex = field(default_factory=SignatureIndex)
    classes: dict[NamedNode, ClassRecord] = field(default_factory=dict)
    parents: dict[NamedNode, set[NamedNode]] = field(default_factory=dict)
    children: dict[NamedNode, set[NamedNode]] = field(default_factory=dict)
    restrictions: Counter[Restriction] = field(default_factory=Counter)
    """How many live classes use each restriction node (shared between classes)."""
    stored_restrictions: set[Restriction] = field(default_factory=set)
    """The restriction nodes the ``memory`` graph holds."""

    def _link(self, child: NamedNode, parent: NamedNode) -> None:
        self._connect(child, parent)
        self.scores.add_to_sums(self.classes[parent], self.classes[child].z, 1)

    def _unlink(self, child: NamedNode, parent: NamedNode) -> None:
        self.parents[child].remove(parent)
        self.children[parent].remove(child)
        below, above = self.classes[child], self.classes[parent]
        below.up.remove(above)
        above.fan_in -= 1
        self.scores.add_to_sums(above, below.z, -1)

    def _connect(self, child: NamedNode, parent: NamedNode) -> None:
        """Record the edge child ⊑ parent (Z sums are the caller's business)."""
        if parent not in self.parents[child]:
            self.parents[child].add(parent)
            self.children[parent].add(child)
            above = self.classes[parent]
            self.classes[child].up.append(above)
            above.fan_in += 1

    # Classes and edges -------------------------------------------------------------------------

    def _register(self, record: ClassRecord, *, indexed: bool = False) -> None:
        """Add a class to the maps and counters (and to the index unless ``indexed``); its Z
        is zero until refreshed."""
        cls, scores = record.iri, self.scores
        if not indexed:
            self.index.add(cls, record.signature)
        self.classes[cls] = record
        self.parents.setdefault(cls, set())
        self.children.setdefault(cls, set())
        self.items.items_of.setdefault(cls, set())
        scores.complexities[record.signature.complexity] += 1
        scores.store_counts[record.store_count] += 1
        scores.retrieve_counts[record.retrieve_count] += 1
        self.restrictions.update(record.signature.items())
        record.z, record.sums, record.up, record.fan_in = (0, 0, 0), [0, 0, 0], [], 0
        if not indexed:
            scores.set_row(cls, record.z)

    def register_all(self, records: list[ClassRecord]) -> None:
        """:meth:`_register` of many indexed classes, each table and counter filled at once."""
        scores = self.scores
        for record in records:
            record.z, record.sums, record.up, record.fan_in = (0, 0, 0), [0, 0, 0], [], 0
        self.classes.update((r.iri, r) for r in records)
        for table in (self.parents, self.children, self.items.items_of):
            for record in records:
                table.setdefault(record.iri, set())
        scores.complexities.update(r.signature.complexity for r in records)
        scores.store_counts.update(r.store_count for r in records)
        scores.retrieve_counts.update(r.retrieve_count for r in records)
        self.restrictions.update(
            itertools.chain.from_iterable(r.signature.items() for r in records)
        )

    def add_class(
        self, record: ClassRecord, ancestors: Iterable[NamedNode] | None = None
    ) -> tuple[set[NamedNode], set[NamedNode], set[tuple[NamedNode, NamedNode]]]:
        """Index a class and link it into the transitively reduced graph; ``ancestors`` are the
        classes its signature is recognised as, when the caller has them already.

        Returns (direct parents, direct children, removed (child, parent) edges): the edges
        between those parents and children now pass through the new class.
        """
        cls = record.iri
        if ancestors is None:
            ancestors = self.index.recognised(record.signature)
        ancestors = set(ancestors)
        descendants = set(self.index.dominating(record.signature))
        # A direct parent is an ancestor with no child among the ancestors, that is, no
        # ancestor's parent (and the other way round for the children): set unions of the
        # edge sets, whose members' hashes are kept, instead of a test per ancestor.
        parents = ancestors.difference(*(self.parents[a] for a in ancestors))
        children = descendants.difference(*(self.children[d] for d in descendants))
        removed: set[tuple[NamedNode, NamedNode]] = set()
        self._register(record)
        for p in parents:
            for c in children & self.children[p]:
                self._unlink(c, p)
                removed.add((c, p))
        for c in children:
            self._link(c, cls)
        # The new class's Z is zero until the refresh derives it, so linking it under its
        # parents adds nothing to their sums: it raises their fan-in and queues them (a learn
        # links a class under hundreds of parents).
        classes, children_of, up = self.classes, self.children, record.up
        self.parents[cls].update(parents)
        for p in parents:
            children_of[p].add(cls)
            above = classes[p]
            up.append(above)
            above.fan_in += 1
        self.scores.touch_below(parents, record)
        return parents, children, removed

    def remove_class(self, cls: NamedNode) -> set[tuple[NamedNode, NamedNode]]:
        """Unlink a class; returns the (child, parent) edges that must now be added so the graph
        stays the transitive reduction of signature dominance."""
        record, scores = self.classes[cls], self.scores
        parents, children = set(self.parents[cls]), set(self.children[cls])
        for p in parents:
            self._unlink(cls, p)
        for c in children:
            self._unlink(c, cls)
        self.classes.pop(cls)
        scores.removed(cls)
        self.index.remove(cls)
        self.parents.pop(cls)
        self.children.pop(cls)
        added: set[tuple[NamedNode, NamedNode]] = set()
        for c in children:
            for p in parents:
                # p covers c unless another parent of c lies between them.
                between = any(
                    q != p and self.classes[q].signature.satisfies(self.classes[p].signature)
                    for q in self.parents[c]
                )
                if not between:
                    self._link(c, p)
                    added.add((c, p))
        move_count(scores.complexities, record.signature.complexity, None)
        move_count(scores.store_counts, record.store_count, None)
        move_count(scores.retrieve_counts, record.retrieve_count, None)
        self.restrictions.subtract(record.signature.items())
        self.restrictions += Counter()  # drop the restrictions no live class uses
        self.items.items_of.pop(cls, None)
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
