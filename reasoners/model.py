"""The in-memory mirror of the scene memory: records, direct subclass edges, maxima, scores.

The store is the source of truth; :mod:`reasoners.persist` fills a :class:`MemoryModel` from
its triples on open, and the memory rebuilds it from the store after a failed transaction.

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

>>> from ontologies.vocab import PLANE, engram
>>> model = MemoryModel(weights=(0.2, 0.2, 0.3, 0.3))
>>> t = dt.datetime(2025, 1, 1, tzinfo=dt.UTC)
>>> sig = Signature({(engram("sphereIsAboveOf"), PLANE): 1})
>>> record = ClassRecord(engram("Scene-1"), sig, 1, 0, 0.0, t, t)
>>> _ = model.add_class(record)
>>> round(model.zeta(record), 9), model.normalised(record)  # fixed point: about 1e-13 off
(0.5, 1.0)
"""

import datetime as dt
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
from reasoners.signature import Key, Signature

__all__ = ["SCALE", "ClassRecord", "ItemRecord", "MemoryModel", "TrashedClass", "TrashedItem"]

SCALE = 1 << 40
"""Fixed-point scale of the ``Z`` terms (resolution about 1e-12)."""

Restriction = tuple[Key, int]
"""One restriction ``≥n p.T`` as ((p, T), n)."""
Derived = tuple[dict[Key, list[int]], dict[int, int], list[tuple[tuple[int, int, int], list[int]]]]
"""The index's bitsets (at least n per key, per complexity) and each class's (Z, child sums)."""


@dataclass
class ClassRecord:
    """A learned scene class: its signature, the raw terms of its score, and the ζ last
    written to the store (``score``, as of its last update; the live ζ is
    :meth:`MemoryModel.zeta`)."""

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
    """The level the last sleep pass gave it (None before its first pass)."""
    z: tuple[int, int, int] = (0, 0, 0)
    """Z_d, Z_s, Z_r in fixed point (SCALE)."""
    sums: list[int] = field(default_factory=lambda: [0, 0, 0])
    """Σ Z_x over the direct children, in fixed point."""
    up: list["ClassRecord"] = field(default_factory=list, repr=False, compare=False)
    """The records of the direct parents (``MemoryModel.parents`` as records, so that
    :meth:`MemoryModel.refresh` walks a branch without hashing IRIs)."""
    fan_in: int = field(default=0, repr=False, compare=False)
    """The number of direct children."""
    mark: int = field(default=0, repr=False, compare=False)
    """The last refresh that queued this record."""
    written_z: tuple[int, int, int] | None = field(default=None, repr=False, compare=False)
    """The Z terms the store holds for this class (the score view), None if none."""


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


@functools.lru_cache(maxsize=4096)
def _log_fixed(count: int) -> int:
    """ln(1 + count) in fixed point."""
    return round(math.log1p(count) * SCALE)


@dataclass
class MemoryModel:
    """Everything the memory needs to answer without querying the store.

    ``weights`` are (a_d, a_c, a_s, a_r) of the semantic score.
    """

    weights: tuple[float, float, float, float] = (0.2, 0.2, 0.3, 0.3)
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
    restrictions: Counter[Restriction] = field(default_factory=Counter)
    """How many live classes use each restriction node (shared between classes)."""
    stored_restrictions: set[Restriction] = field(default_factory=set)
    """The restriction nodes the ``memory`` graph holds."""
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
    def max_item_complexity(self) -> int:
        return max(self.item_complexities, default=0)

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
        _move(self.store_counts, record.store_count, store)
        _move(self.retrieve_counts, record.retrieve_count, retrieve)
        record.store_count, record.retrieve_count = store, retrieve
        self._touch(record)

    def _own(self, record: ClassRecord) -> tuple[int, int, int]:
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
        # :meth:`_own` inlined (the same arithmetic): this loop runs once per ancestor of what
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
        self._set_rows(changed)
        self.unwritten.update(record.iri for record in changed)

    def _touch(self, record: ClassRecord) -> None:
        """Queue a class whose own terms or children changed for the next refresh."""
        self._dirty.add(record.iri)
        self._dirty_top = max(self._dirty_top, record.signature.complexity)

    def _set_row(self, cls: NamedNode, z: tuple[int, int, int]) -> None:
        position = self.index.position(cls)
        self._grow(position)
        self._z[:, position] = (z[0] / SCALE, z[1] / SCALE, z[2] / SCALE)
        self._version += 1

    def _set_rows(self, records: list[ClassRecord]) -> None:
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

    def _link(self, child: NamedNode, parent: NamedNode) -> None:
        self._connect(child, parent)
        self._add_to_sums(self.classes[parent], self.classes[child].z, 1)

    def _unlink(self, child: NamedNode, parent: NamedNode) -> None:
        self.parents[child].remove(parent)
        self.children[parent].remove(child)
        below, above = self.classes[child], self.classes[parent]
        below.up.remove(above)
        above.fan_in -= 1
        self._add_to_sums(above, below.z, -1)

    def _add_to_sums(self, record: ClassRecord, z: tuple[int, int, int], sign: int) -> None:
        """Add (or with ``sign`` -1 take away) a child's Z to a class's sums, and queue it."""
        for x in range(3):
            record.sums[x] += sign * z[x]
        self._touch(record)

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
        cls = record.iri
        if not indexed:
            self.index.add(cls, record.signature)
        self.classes[cls] = record
        self.parents.setdefault(cls, set())
        self.children.setdefault(cls, set())
        self.items_of.setdefault(cls, set())
        self.complexities[record.signature.complexity] += 1
        self.store_counts[record.store_count] += 1
        self.retrieve_counts[record.retrieve_count] += 1
        self.restrictions.update(record.signature.items())
        record.z, record.sums, record.up, record.fan_in = (0, 0, 0), [0, 0, 0], [], 0
        if not indexed:
            self._set_row(cls, record.z)

    def _register_all(self, records: list[ClassRecord]) -> None:
        """:meth:`_register` of many indexed classes, each table and counter filled at once."""
        for record in records:
            record.z, record.sums, record.up, record.fan_in = (0, 0, 0), [0, 0, 0], [], 0
        self.classes.update((r.iri, r) for r in records)
        for table in (self.parents, self.children, self.items_of):
            for record in records:
                table.setdefault(record.iri, set())
        self.complexities.update(r.signature.complexity for r in records)
        self.store_counts.update(r.store_count for r in records)
        self.retrieve_counts.update(r.retrieve_count for r in records)
        self.restrictions.update(
            itertools.chain.from_iterable(r.signature.items() for r in records)
        )

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
        records = list(records)
        self.index.add_all((r.iri, r.signature) for r in records)
        self._register_all(records)
        classes, parents, children = self.classes, self.parents, self.children
        for child, parent in edges:
            below, above = classes.get(child), classes.get(parent)
            if below is None or above is None or parent in parents[child]:
                continue
            parents[child].add(parent)
            children[parent].add(child)
            below.up.append(above)
            above.fan_in += 1
        ordered = sorted(classes.values(), key=lambda r: -r.signature.complexity)
        own = self._own
        for record in ordered:  # children (more complex) before parents
            record.z = z = own(record)
            for above in record.up:
                sums = above.sums
                sums[0] += z[0]
                sums[1] += z[1]
                sums[2] += z[2]
        self._set_rows(ordered)
        self._dirty.clear()
        self._dirty_top = 0
        self.unwritten = {r.iri for r in self.classes.values() if r.written_z != r.z}

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
        """
        if self.classes:
            raise ValueError("restore: the model is not empty")
        nodes = [r.iri for r in records]
        self.index.restore(
            list(zip(nodes, (r.signature for r in records), strict=True)), at_least, by_complexity
        )
        self.classes = dict(zip(nodes, records, strict=True))
        self.parents = dict(zip(nodes, parents, strict=True))
        self.children = dict(zip(nodes, children, strict=True))
        self.items_of = {node: set() for node in nodes}
        self.complexities = Counter(r.signature.complexity for r in records)
        self.store_counts = Counter(r.store_count for r in records)
        self.retrieve_counts = Counter(r.retrieve_count for r in records)
        self.restrictions = restrictions
        self._set_rows(records)
        self._dirty.clear()
        self._dirty_top = 0
        self.unwritten = {r.iri for r in records if r.written_z != r.z}

    def derived(self) -> "Derived | None":
        """What :meth:`load` would derive for :attr:`classes` (in their order), for
        :meth:`restore`: the index's bitsets (squeezed where classes were removed) and each
        class's Z and child sums, all current; None if the index does not hold the classes in
        their order, so that a load re-derives them."""
        self.refresh()
        if self.index.classes() != list(self.classes):
            return None
        at_least, by_complexity = self.index.state()
        scores = [(r.z, list(r.sums)) for r in self.classes.values()]
        return (at_least, by_complexity, scores)

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
        for p in parents:
            self._link(cls, p)
        self._touch(record)
        return parents, children, removed

    def remove_class(self, cls: NamedNode) -> set[tuple[NamedNode, NamedNode]]:
        """Unlink a class; returns the (child, parent) edges that must now be added so the graph
        stays the transitive reduction of signature dominance."""
        record = self.classes[cls]
        parents, children = set(self.parents[cls]), set(self.children[cls])
        for p in parents:
            self._unlink(cls, p)
        for c in children:
            self._unlink(c, cls)
        self.classes.pop(cls)
        self._set_row(cls, (0, 0, 0))
        self.index.remove(cls)
        self.parents.pop(cls)
        self.children.pop(cls)
        self._dirty.discard(cls)
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
        _move(self.complexities, record.signature.complexity, None)
        _move(self.store_counts, record.store_count, None)
        _move(self.retrieve_counts, record.retrieve_count, None)
        self.restrictions.subtract(record.signature.items())
        self.restrictions += Counter()  # drop the restrictions no live class uses
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

    def add_items(self, records: Iterable[ItemRecord]) -> None:
        """:meth:`add_item` of many items, the counter filled at once."""
        records = list(records)
        self.items.update((r.iri, r) for r in records)
        items_of = self.items_of
        for record in records:
            items_of.setdefault(record.cls, set()).add(record.iri)
        self.item_complexities.update(r.complexity for r in records)

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
