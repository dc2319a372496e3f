"""The classes' semantic scores: the weights, the maxima, the Z terms kept current, ζ.

Semantic scores are derived, not stored state. ζ is linear in the class's own terms
(DESIGN.md, step 7): with ``Z_x = u_x + a_c·mean(Z_x of direct children)`` for the three own
terms ``u_d = d``, ``u_s = ln(1+s)``, ``u_r = ln(1+r)``,

    ζ = a_d·Z_d / max d  +  a_s·Z_s / ln(1+max s)  +  a_r·Z_r / ln(1+max r)

which unfolds to ``a_d·d̂ + a_c·mean(ζ of direct children) + a_s·ŝ + a_r·r̂``. The ``Z`` terms
do not depend on the maxima, so a change of maximum changes three coefficients and rewrites
nothing; a change of a class's counts or children changes the ``Z`` of that class and of its
ancestors only (synaptic consolidation), propagated bottom-up. ``Z`` is kept in fixed point
(integers) so that the incremental sums equal a recomputation from scratch bit for bit: a
reopened memory derives exactly the scores the running one had.

The Z terms and child sums live on the :class:`~reasoners.records.ClassRecord`\\ s (the refresh
walks them record to record); the table keeps what is pending, one row of Z per index slot for
the vectorised maxima, and the counters of the maxima. It reads the class graph's records and
index and never changes them: the graph tells the table what changed (:meth:`ScoreTable.touch`,
:meth:`ScoreTable.add_to_sums`, :meth:`ScoreTable.set_row`, :meth:`ScoreTable.removed`).
"""

import functools
import itertools
import math
from collections import Counter
from collections.abc import Iterable
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray
from pyoxigraph import NamedNode

from reasoners.index import SignatureIndex
from reasoners.records import ClassRecord

__all__ = ["SCALE", "ScoreTable", "move_count"]

SCALE = 1 << 40
"""Fixed-point scale of the ``Z`` terms (resolution about 1e-12)."""


@functools.lru_cache(maxsize=4096)
def _log_fixed(count: int) -> int:
    """ln(1 + count) in fixed point."""
    return round(math.log1p(count) * SCALE)


@dataclass
class ScoreTable:
    """The live scores of the classes in ``classes`` (indexed by ``index``: both the class
    graph's, read here, never changed).

    ``weights`` are (a_d, a_c, a_s, a_r) of the semantic score.
    """

    index: SignatureIndex = field(repr=False, compare=False)
    classes: dict[NamedNode, ClassRecord] = field(repr=False, compare=False)
    weights: tuple[float, float, float, float] = (0.2, 0.2, 0.3, 0.3)
    complexities: Counter[int] = field(default_factory=Counter)
    store_counts: Counter[int] = field(default_factory=Counter)
    retrieve_counts: Counter[int] = field(default_factory=Counter)
    scored: dict[NamedNode, float] = field(default_factory=dict)
    """Each class's ζ as of the last sleep pass, for those no update re-scored since (the
    others': ``ClassRecord.score``); kept in memory only, for the history's periodic
    re-scoring (reasoners.history.sleep_levels)."""
    unwritten: set[NamedNode] = field(default_factory=set)
    """Classes whose Z changed since the score view was last written."""
    written_factors: tuple[float, float, float, float] | None = None
    """The score factors and largest raw ζ the memory state holds (the score view)."""
    _dirty: set[NamedNode] = field(default_factory=set)
    _dirty_top: int = 0
    """At least the largest complexity in ``_dirty`` (0 when nothing is pending)."""
    _z: NDArray[np.float64] = field(default_factory=lambda: np.zeros((3, 64)))
    _top: tuple[tuple[int, tuple[float, float, float]], float] | None = None
    _version: int = 0
    _refreshes: int = 0

    # Maxima ------------------------------------------------------------------------------------

    @property
    def max_complexity(self) -> int:
        return max(self.complexities, default=0)

    @property
    def max_store(self) -> int:
        return max(self.store_counts, default=0)

    @property
    def max_retrieve(self) -> int:
        return max(self.retrieve_counts, default=0)

    # Scores ------------------------------------------------------------------------------------

    def coefficients(self) -> tuple[float, float, float]:
        """The factors that turn Z_d, Z_s, Z_r into ζ with the current maxima."""
        a_d, _, a_s, a_r = self.weights
        d, s, r = self.max_complexity, self.max_store, self.max_retrieve
        return (
            a_d / d if d else 0.0,
            a_s / math.log1p(s) if s else 0.0,
            a_r / math.log1p(r) if r else 0.0,
        )

    def zeta(self, record: ClassRecord) -> float:
        """The live raw ζ of a class (brought up to date by refreshing only the classes at
        least as complex as it: its Z depends on its descendants alone)."""
        self.refresh(down_to=record.signature.complexity)
        cd, cs, cr = self.coefficients()
        zd, zs, zr = record.z
        return cd * (zd / SCALE) + cs * (zs / SCALE) + cr * (zr / SCALE)

    def zetas(self) -> dict[NamedNode, float]:
        """The live raw ζ of every class."""
        self.refresh()
        cd, cs, cr = self.coefficients()
        return {
            cls: cd * (r.z[0] / SCALE) + cs * (r.z[1] / SCALE) + cr * (r.z[2] / SCALE)
            for cls, r in self.classes.items()
        }

    @property
    def max_score(self) -> float:
        """The largest live ζ (vectorised over all classes; cached until something changes)."""
        self.refresh()
        key = (self._version, self.coefficients())
        if self._top is None or self._top[0] != key:
            best = 0.0
            slots = self.index.slots()
            if self.classes:
                cd, cs, cr = key[1]
                z = self._z[:, : len(slots)]
                position = int(np.argmax(cd * z[0] + cs * z[1] + cr * z[2]))
                cls = slots[position]
                if cls is not None:
                    best = self.zeta(self.classes[cls])
            self._top = (key, best)
        return self._top[1]

    def top(self, count: int) -> list[tuple[NamedNode, float]]:
        """The ``count`` classes of largest live ζ as (class, ζ), best first, ties by IRI:
        candidates picked over all classes at once in numpy, then ranked by exact ζ."""
        self.refresh()
        slots = self.index.slots()
        if not self.classes or count < 1:
            return []
        cd, cs, cr = self.coefficients()
        z = self._z[:, : len(slots)]
        values = cd * z[0] + cs * z[1] + cr * z[2]
        live = np.array([cls is not None for cls in slots])
        values = np.where(live, values, -np.inf)
        # every class tied with the count-th best is a candidate, so ties resolve by IRI
        keep = min(count, int(live.sum()))
        cut = np.partition(values, len(values) - keep)[len(values) - keep]
        candidates = [slots[int(i)] for i in np.flatnonzero(values >= cut - 1e-12)]
        ranked = sorted(
            ((cls, self.zeta(self.classes[cls])) for cls in candidates if cls is not None),
            key=lambda kv: (-kv[1], kv[0].value),
        )
        return ranked[:count]

    def normalised(self, record: ClassRecord) -> float:
        top = self.max_score
        return self.zeta(record) / top if top > 0 else 0.0

    def set_counts(self, record: ClassRecord, *, store: int, retrieve: int) -> None:
        move_count(self.store_counts, record.store_count, store)
        move_count(self.retrieve_counts, record.retrieve_count, retrieve)
        record.store_count, record.retrieve_count = store, retrieve
        self.touch(record)

    def own(self, record: ClassRecord) -> tuple[int, int, int]:
        """A class's Z from its own terms and its children's sums (as :meth:`refresh` derives
        it; the bulk load's derivation)."""
        u_d = record.signature.complexity * SCALE
        u_s, u_r = _log_fixed(record.store_count), _log_fixed(record.retrieve_count)
        n = record.fan_in
        if not n:
            return (u_d, u_s, u_r)
        a_c, sums = self.weights[1], record.sums
        return (
            u_d + round(a_c * (sums[0] / n)),
            u_s + round(a_c * (sums[1] / n)),
            u_r + round(a_c * (sums[2] / n)),
        )

    def refresh(self, down_to: int = 0) -> None:
        """Re-derive Z of the changed classes and their ancestors, children before parents: a
        child is always more complex than its parents, so classes are taken by decreasing
        complexity (classes of equal complexity never lie on one branch).

        With ``down_to``, stop before the classes of lower complexity (they stay pending): every
        class of complexity ``down_to`` or more is then current.
        """
        if self._dirty_top < down_to or not self._dirty:
            return
        self._refreshes += 1
        mark = self._refreshes
        waiting: dict[int, list[ClassRecord]] = {}
        for cls in self._dirty:
            record = self.classes[cls]
            record.mark = mark
            waiting.setdefault(record.signature.complexity, []).append(record)
        self._dirty.clear()
        changed: list[ClassRecord] = []
        keep, queue = changed.append, waiting.setdefault
        a_c, log_fixed = self.weights[1], _log_fixed
        # :meth:`own` inlined (the same arithmetic): this loop runs once per ancestor of what
        # changed, thousands of times per update in a large memory
        while waiting:
            complexity = max(waiting)
            if complexity < down_to:
                break
            u_d = complexity * SCALE
            for record in waiting.pop(complexity):
                n = record.fan_in
                if n:
                    s0, s1, s2 = record.sums
                    new = (
                        u_d + round(a_c * (s0 / n)),
                        log_fixed(record.store_count) + round(a_c * (s1 / n)),
                        log_fixed(record.retrieve_count) + round(a_c * (s2 / n)),
                    )
                else:
                    new = (u_d, log_fixed(record.store_count), log_fixed(record.retrieve_count))
                old = record.z
                if new == old:
                    continue
                record.z = new
                keep(record)
                d0, d1, d2 = new[0] - old[0], new[1] - old[1], new[2] - old[2]
                # one pass over the parents: add the change to their sums and queue them
                if d0 or d2:
                    for above in record.up:
                        sums = above.sums
                        sums[0] += d0
                        sums[1] += d1
                        sums[2] += d2
                        if above.mark != mark:
                            above.mark = mark
                            queue(above.signature.complexity, []).append(above)
                else:  # a reinforce changes the store term alone
                    for above in record.up:
                        above.sums[1] += d1
                        if above.mark != mark:
                            above.mark = mark
                            queue(above.signature.complexity, []).append(above)
        self._dirty.update(record.iri for level in waiting.values() for record in level)
        self._dirty_top = max(waiting, default=0)
        self.set_rows(changed)
        self.unwritten.update(record.iri for record in changed)

    def touch(self, record: ClassRecord) -> None:
        """Queue a class whose own terms or children changed for the next refresh."""
        self._dirty.add(record.iri)
        self._dirty_top = max(self._dirty_top, record.signature.complexity)

    def touch_below(self, classes: Iterable[NamedNode], record: ClassRecord) -> None:
        """:meth:`touch` of ``record`` and of ``classes``, none of them more complex than it."""
        self._dirty.update(classes)
        self.touch(record)

    def set_row(self, cls: NamedNode, z: tuple[int, int, int]) -> None:
        """Set the score row of an indexed class."""
        position = self.index.position(cls)
        self._grow(position)
        self._z[:, position] = (z[0] / SCALE, z[1] / SCALE, z[2] / SCALE)
        self._version += 1

    def set_rows(self, records: list[ClassRecord]) -> None:
        """Set the score rows of indexed classes to their records' Z."""
        if not records:
            return
        positions = self.index.positions(r.iri for r in records)
        self._grow(max(positions))
        z = itertools.chain.from_iterable(r.z for r in records)
        rows = np.fromiter(z, dtype=np.float64, count=3 * len(records)).reshape(-1, 3)
        self._z[:, positions] = rows.T / SCALE
        self._version += 1

    def _grow(self, position: int) -> None:
        if position >= self._z.shape[1]:
            grown = np.zeros((3, max(2 * self._z.shape[1], position + 1)))
            grown[:, : self._z.shape[1]] = self._z
            self._z = grown

    def add_to_sums(self, record: ClassRecord, z: tuple[int, int, int], sign: int) -> None:
        """Add (or with ``sign`` -1 take away) a child's Z to a class's sums, and queue it."""
        for x in range(3):
            record.sums[x] += sign * z[x]
        self.touch(record)

    def removed(self, cls: NamedNode) -> None:
        """Clear the row of a class leaving the graph (still indexed) and drop it from what is
        pending."""
        self.set_row(cls, (0, 0, 0))
        self._dirty.discard(cls)

    def loaded(self, records: list[ClassRecord]) -> None:
        """Take the Z that a bulk load gave ``records`` (every class) as current: their rows
        set, nothing pending, unwritten the classes whose Z differs from the store's."""
        self.set_rows(records)
        self._dirty.clear()
        self._dirty_top = 0
        self.unwritten = {r.iri for r in records if r.written_z != r.z}


def move_count(counter: Counter[int], old: int | None, new: int | None) -> None:
    """Move one count in ``counter`` from ``old`` to ``new`` (None: none), dropping keys at 0."""
    if old is not None:
        counter[old] -= 1
        if counter[old] <= 0:
            del counter[old]
    if new is not None:
        counter[new] += 1
