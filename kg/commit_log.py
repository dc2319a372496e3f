"""The store's recent commits, kept in memory so that a copy of the store can catch up cheaply.

The SPARQL query workers (:mod:`kg.sandbox`) each hold a private copy of the store (a
hard-linked backup) and, before a query, replay the commits made since their copy's generation:
a few quads per commit instead of a new backup and a fresh open each time a writer has
committed.

A commit is recorded as what was applied: the quads inserted (a write with no deletion), or the
SPARQL update text (``CLEAR`` / ``DELETE DATA`` / ``INSERT DATA``, terms written out). Each
makes a set of quads present or absent, so replaying a commit that a copy already holds changes
nothing: a copy taken while writers commit may be replayed from the generation read before the
backup started. A write that is not recorded (a bulk load) breaks the log: copies older than it
must be taken again.

>>> from pyoxigraph import NamedNode, Quad
>>> log = CommitLog(max_quads=2)
>>> q = Quad(NamedNode("http://x/a"), NamedNode("http://x/p"), NamedNode("http://x/b"),
...          NamedNode("http://x/g"))
>>> log.record(1, inserts=[q]); log.record(2, update="CLEAR SILENT GRAPH <http://x/g>")
>>> [c.generation for c in log.since(0, 2)], log.since(1, 1)
([1, 2], [])
>>> log.record(3, inserts=[q, q])  # past max_quads: the oldest commits are dropped
>>> log.since(0, 3) is None, [c.generation for c in log.since(2, 3)]
(True, [3])
"""

import threading
from collections.abc import Sequence
from dataclasses import dataclass

from pyoxigraph import Quad

__all__ = ["Commit", "CommitLog"]


@dataclass(frozen=True)
class Commit:
    """One committed write: ``inserts`` (quads added), or ``update`` (SPARQL update text)."""

    generation: int
    inserts: Sequence[Quad] = ()
    update: str | None = None

    @property
    def size(self) -> int:
        """Quads (or, for an update, characters / 100) it holds: what keeping it costs."""
        return len(self.inserts) + (len(self.update) // 100 + 1 if self.update else 0)


class CommitLog:
    """The latest commits of one store, in order, up to about ``max_quads`` quads in all.

    It holds every commit after generation :attr:`floor`; :meth:`since` answers None for an
    older generation (the commits were dropped, or a write was not recorded).
    """

    def __init__(self, *, max_quads: int = 200_000) -> None:
        if max_quads < 1:
            raise ValueError(f"max_quads: got {max_quads}, expected at least 1")
        self.max_quads = max_quads
        self._lock = threading.Lock()
        self._commits: list[Commit] = []
        self._first = 0  # index in _commits of the oldest kept commit
        self._quads = 0
        self.floor = 0
        """The log holds every commit made after this generation."""

    def record(
        self, generation: int, *, inserts: Sequence[Quad] = (), update: str | None = None
    ) -> None:
        """Append the commit that made the store's generation ``generation``."""
        commit = Commit(generation, inserts, update)
        with self._lock:
            if generation != self.floor + len(self._commits) - self._first + 1:
                self._restart(generation - 1)  # a gap: only later commits can be replayed
            self._commits.append(commit)
            self._quads += commit.size
            while self._quads > self.max_quads and self._first < len(self._commits):
                dropped = self._commits[self._first]
                self._first += 1
                self._quads -= dropped.size
                self.floor = dropped.generation
            if self._first > 1024 and self._first * 2 > len(self._commits):
                del self._commits[: self._first]
                self._first = 0

    def unrecorded(self, generation: int) -> None:
        """The store reached ``generation`` by a write that was not recorded."""
        with self._lock:
            self._restart(generation)

    def since(self, generation: int, upto: int) -> list[Commit] | None:
        """The commits after ``generation`` up to ``upto`` included, or None if some are gone."""
        with self._lock:
            if generation < self.floor:
                return None
            start = self._first + generation - self.floor
            end = self._first + max(upto, generation) - self.floor
            return self._commits[start:end]

    def _restart(self, generation: int) -> None:
        self._commits, self._first, self._quads, self.floor = [], 0, 0, generation
