"""Pending writes that several memory operations share before one commit.

A :class:`kg.transaction.Transaction` applies all deletions before all insertions, which is
right for one operation but wrong for two in a row: the second operation's deletion of a value
the first one inserted would be undone by that insertion. :class:`PendingWrites` keeps the net
effect of a sequence of operations instead (a deletion also cancels an earlier insertion), so
that the scene memory can run every memory directive of a directive list into one transaction,
and it answers reads as the store will be once those writes commit (:meth:`quads`).

>>> from pyoxigraph import Literal
>>> from kg import Store
>>> from ontologies.vocab import MEMORY, SCORE, engram
>>> writes = PendingWrites()
>>> writes.insert(engram("Scene-1"), SCORE, Literal(1), MEMORY)
>>> writes.delete(engram("Scene-1"), SCORE, Literal(1), MEMORY)
>>> writes.insert(engram("Scene-1"), SCORE, Literal(2), MEMORY)
>>> [q.object.value for q in writes.quads(Store(), engram("Scene-1"))]
['2']
"""

from collections import defaultdict
from collections.abc import Iterator
from dataclasses import dataclass, field

from pyoxigraph import Literal, NamedNode, Quad

from kg.store import Store
from kg.transaction import Object, Pattern, Subject, Transaction

__all__ = ["PendingView", "PendingWrites", "matches"]


def matches(
    quad: Quad,
    subject: object,
    predicate: object,
    obj: object,
    graph: object,
) -> bool:
    """Whether ``quad`` matches the pattern (``None`` matches anything)."""
    return (
        (subject is None or quad.subject == subject)
        and (predicate is None or quad.predicate == predicate)
        and (obj is None or quad.object == obj)
        and (graph is None or quad.graph_name == graph)
    )


@dataclass
class PendingWrites(Transaction):
    """A transaction whose operations compose in order (see the module docstring)."""

    _inserted: set[Quad] = field(default_factory=set, repr=False)
    _deleted: set[Quad] = field(default_factory=set, repr=False)
    _subjects: defaultdict[object, set[Quad]] = field(
        default_factory=lambda: defaultdict(set), repr=False
    )
    """The inserted quads by subject, so that a deletion by pattern with a subject looks at
    that subject's alone (a sleep pass inserts a million quads, then deletes a few by pattern)."""

    def insert(self, subject: Subject, predicate: NamedNode, obj: Object, graph: NamedNode) -> None:
        quad = self._quad(subject, predicate, obj, graph)
        self.inserts.append(quad)
        self._inserted.add(quad)
        # the subject as given unless it was a blank node (reading quad.subject builds a new
        # term: about half of this method's time)
        self._subjects[subject if type(subject) is NamedNode else quad.subject].add(quad)

    def delete(self, subject: Subject, predicate: NamedNode, obj: Object, graph: NamedNode) -> None:
        quad = self._quad(subject, predicate, obj, graph)
        if quad in self._inserted:
            self._inserted.discard(quad)
            self._subjects[quad.subject].discard(quad)
            self.inserts = [q for q in self.inserts if q != quad]
        self.deletes.append(quad)
        self._deleted.add(quad)

    def delete_matching(
        self,
        subject: NamedNode | None = None,
        predicate: NamedNode | None = None,
        obj: NamedNode | Literal | None = None,
        *,
        graph: NamedNode,
    ) -> None:
        super().delete_matching(subject, predicate, obj, graph=graph)
        candidates = self._inserted if subject is None else self._subjects.get(subject, set())
        doomed = {q for q in candidates if matches(q, subject, predicate, obj, graph)}
        if doomed:
            self._inserted -= doomed
            for quad in doomed:
                self._subjects[quad.subject].discard(quad)
            self.inserts = [q for q in self.inserts if q not in doomed]

    def quads(
        self,
        store: Store,
        subject: NamedNode | None = None,
        predicate: NamedNode | None = None,
        obj: NamedNode | Literal | None = None,
        graph: NamedNode | None = None,
    ) -> Iterator[Quad]:
        """The quads of ``store`` matching the pattern as they will be after the commit."""
        seen: set[Quad] = set()
        for quad in store.quads(subject, predicate, obj, graph):
            if quad in self._deleted or any(_hit(p, quad) for p in self.patterns):
                continue
            seen.add(quad)
            yield quad
        for quad in list(self.inserts):
            if quad not in seen and matches(quad, subject, predicate, obj, graph):
                seen.add(quad)
                yield quad

    def view(self, store: Store) -> "PendingView":
        """A reader of ``store`` as it will be after these writes commit."""
        return PendingView(store, self)

    def copy_into(self, tx: Transaction) -> None:
        """Add these writes to ``tx`` (whose other writes are to other graphs)."""
        tx.deletes.extend(self.deletes)
        tx.patterns.extend(self.patterns)
        tx.inserts.extend(self.inserts)


def _hit(pattern: Pattern, quad: Quad) -> bool:
    return matches(quad, pattern.subject, pattern.predicate, pattern.object, pattern.graph)


@dataclass(frozen=True)
class PendingView:
    """``store`` as it will be once ``writes`` commit (a :class:`QuadReader`)."""

    store: Store
    writes: PendingWrites

    def quads(
        self,
        subject: NamedNode | None = None,
        predicate: NamedNode | None = None,
        obj: NamedNode | Literal | None = None,
        graph: NamedNode | None = None,
    ) -> Iterator[Quad]:
        return self.writes.quads(self.store, subject, predicate, obj, graph)
