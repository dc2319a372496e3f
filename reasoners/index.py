"""An in-memory index of learned signatures: recognition without comparing every class.

Each class gets a bit position. For every signature key k and count v the index keeps a bitset
of the classes whose restriction on k is at least v. A scene with counts m(k) fails class C
exactly when some key has C[k] > m(k), so the recognised classes are

    all classes  AND NOT  OR_k  atLeast[k][m(k) + 1]

one big-integer operation per distinct key in the memory (a few hundred at most), whatever
the number of classes. Specialisations of a cue (classes whose counts dominate it) are
AND_k atLeast[k][cue(k)]. The bitsets are rebuilt from the store's triples on open.

>>> from ontologies.vocab import PLANE, SPHERE, engram
>>> index = SignatureIndex()
>>> above = Signature({(engram("sphereIsAboveOf"), PLANE): 1})
>>> both = Signature({(engram("sphereIsAboveOf"), PLANE): 1, (engram("planeIsBelowOf"), SPHERE): 2})
>>> index.add(engram("Scene-1"), above); index.add(engram("Scene-2"), both)
>>> [c.value[-7:] for c in index.recognised(both)]
['Scene-1', 'Scene-2']
>>> [c.value[-7:] for c in index.dominating(above)]
['Scene-1', 'Scene-2']
"""

from collections import defaultdict
from collections.abc import Iterable, Iterator, Sequence

import numpy as np
from pyoxigraph import NamedNode

from reasoners.signature import Key, Signature

__all__ = ["SignatureIndex", "bits"]


def bits(value: int) -> Iterator[int]:
    """The positions of the set bits of ``value``, lowest first."""
    text = bin(value)[:1:-1]  # least significant first, without the '0b'
    position = text.find("1")
    while position >= 0:
        yield position
        position = text.find("1", position + 1)


def _pack(members: "np.ndarray[tuple[int], np.dtype[np.bool_]]") -> int:
    """The bitset whose bit k is ``members[k]``."""
    return int.from_bytes(np.packbits(members, bitorder="little").tobytes(), "little")


def _bitset(positions: Sequence[int], size: int) -> int:
    members = np.zeros(size, dtype=bool)
    members[list(positions)] = True
    return _pack(members)


class SignatureIndex:
    """Bitset index from signature keys and counts to learned classes."""

    def __init__(self) -> None:
        self._at_least: dict[Key, list[int]] = {}
        self._position: dict[NamedNode, int] = {}
        self._classes: list[NamedNode | None] = []
        self._signature: dict[NamedNode, Signature] = {}
        self._by_signature: dict[Signature, NamedNode] = {}
        self._by_complexity: dict[int, int] = defaultdict(int)
        self._live = 0

    def __len__(self) -> int:
        return len(self._signature)

    def __contains__(self, cls: object) -> bool:
        return cls in self._signature

    def signature(self, cls: NamedNode) -> Signature:
        return self._signature[cls]

    def position(self, cls: NamedNode) -> int:
        """The bit position of an indexed class (stable until it is removed)."""
        return self._position[cls]

    def positions(self, classes: Iterable[NamedNode]) -> list[int]:
        """:meth:`position` of each of ``classes``."""
        return list(map(self._position.__getitem__, classes))

    def slots(self) -> list[NamedNode | None]:
        """The class at every bit position (None where a class was removed)."""
        return self._classes

    def classes(self) -> list[NamedNode]:
        """Every indexed class, in the order they were added."""
        return [cls for cls in self._classes if cls is not None]

    def with_signature(self, signature: Signature) -> NamedNode | None:
        """The class learned with exactly this signature, if any."""
        return self._by_signature.get(signature)

    def add(self, cls: NamedNode, signature: Signature) -> None:
        position = len(self._classes)
        self._classes.append(cls)
        self._position[cls] = position
        self._signature[cls] = signature
        self._by_signature[signature] = cls
        bit = 1 << position
        self._live |= bit
        self._by_complexity[signature.complexity] |= bit
        for key, n in signature.items():
            levels = self._at_least.setdefault(key, [0])
            while len(levels) <= n:
                levels.append(0)
            for v in range(1, n + 1):
                levels[v] |= bit

    def add_all(self, entries: Iterable[tuple[NamedNode, Signature]]) -> None:
        """Index many classes, as :meth:`add` one after the other would, but building each
        bitset once (adding one by one copies every bitset it touches: quadratic at 100k)."""
        start = len(self._classes)
        exact: dict[Key, list[list[int]]] = {}
        by_complexity: dict[int, list[int]] = defaultdict(list)
        for position, (cls, signature) in enumerate(entries, start=start):
            self._classes.append(cls)
            self._position[cls] = position
            self._signature[cls] = signature
            self._by_signature[signature] = cls
            by_complexity[signature.complexity].append(position)
            for key, n in signature.items():
                per_count = exact.setdefault(key, [])
                while len(per_count) < n:
                    per_count.append([])
                per_count[n - 1].append(position)
        size = len(self._classes)
        if size == start:
            return
        self._live |= _bitset(range(start, size), size)
        for d, positions in by_complexity.items():
            self._by_complexity[d] |= _bitset(positions, size)
        for key, per_count in exact.items():
            levels = self._at_least.setdefault(key, [0])
            while len(levels) <= len(per_count):
                levels.append(0)
            members = np.zeros(size, dtype=bool)
            for n in range(len(per_count), 0, -1):  # at least n: count n or more
                members[per_count[n - 1]] = True
                levels[n] |= _pack(members)

    def state(self) -> tuple[dict[Key, list[int]], dict[int, int]]:
        """The bitsets (at least n per key, per complexity) of the live classes in their order,
        as :meth:`add_all` of those classes alone would build them (removed positions squeezed
        out, levels no class reaches any more dropped), for :meth:`restore`."""
        size = len(self._classes)
        if self._live == (1 << size) - 1:
            return {key: list(levels) for key, levels in self._at_least.items()}, dict(
                self._by_complexity
            )
        live = np.array([cls is not None for cls in self._classes], dtype=bool)

        def squeezed(value: int) -> int:
            packed = np.frombuffer(value.to_bytes((size + 7) // 8, "little"), dtype=np.uint8)
            return _pack(np.unpackbits(packed, bitorder="little")[:size].astype(bool)[live])

        at_least: dict[Key, list[int]] = {}
        for key, levels in self._at_least.items():
            kept = [0, *(squeezed(level) for level in levels[1:])]
            while len(kept) > 1 and not kept[-1]:
                kept.pop()
            if len(kept) > 1:
                at_least[key] = kept
        by_complexity = {d: squeezed(members) for d, members in self._by_complexity.items()}
        return at_least, {d: members for d, members in by_complexity.items() if members}

    def restore(
        self,
        entries: Sequence[tuple[NamedNode, Signature]],
        at_least: dict[Key, list[int]],
        by_complexity: dict[int, int],
    ) -> None:
        """Index ``entries`` at positions 0, 1, ... from bitsets :meth:`state` gave for the same
        classes in the same order (an empty index only): no bitset is rebuilt."""
        if self._classes:
            raise ValueError("restore: the index is not empty")
        self._classes = [cls for cls, _ in entries]
        self._position = {cls: k for k, (cls, _) in enumerate(entries)}
        self._signature = dict(entries)
        self._by_signature = {signature: cls for cls, signature in entries}
        self._by_complexity = defaultdict(int, by_complexity)
        self._at_least = at_least
        self._live = (1 << len(self._classes)) - 1

    def remove(self, cls: NamedNode) -> None:
        position = self._position.pop(cls)
        signature = self._signature.pop(cls)
        del self._by_signature[signature]
        self._classes[position] = None
        mask = ~(1 << position)
        self._live &= mask
        self._by_complexity[signature.complexity] &= mask
        if not self._by_complexity[signature.complexity]:
            del self._by_complexity[signature.complexity]
        for key, n in signature.items():
            levels = self._at_least[key]
            for v in range(1, n + 1):
                levels[v] &= mask

    def _members(self, value: int) -> list[NamedNode]:
        classes = self._classes
        return [classes[p] for p in bits(value)]  # type: ignore[misc]

    def recognised(self, signature: Signature) -> list[NamedNode]:
        """The classes whose every restriction the signature meets (its generalisations and,
        when learned, itself)."""
        failing = 0
        get = signature.get
        for key, levels in self._at_least.items():
            needed = get(key, 0) + 1
            if needed < len(levels):
                failing |= levels[needed]
        return self._members(self._live & ~failing)

    def dominating(self, signature: Signature) -> list[NamedNode]:
        """The classes that meet every restriction of ``signature`` (its specialisations and,
        when learned, itself)."""
        result = self._live
        for key, n in signature.items():
            levels = self._at_least.get(key)
            if levels is None or n >= len(levels):
                return []
            result &= levels[n]
            if not result:
                return []
        return self._members(result)

    def most_similar(self, signature: Signature, limit: int) -> list[tuple[NamedNode, float]]:
        """Up to ``limit`` classes with the highest weighted Jaccard similarity Σmin/Σmax to
        ``signature`` (above 0), best first, ties in learning order.

        Σmin for every class at once is a sum of bitsets (one per key and count of the cue),
        kept as bit-sliced counters; classes are then visited bucket by bucket, in decreasing
        order of similarity m / (d_cue + d_class - m).
        """
        slices: list[int] = []
        for key, n in signature.items():
            levels = self._at_least.get(key)
            if levels is None:
                continue
            for v in range(1, min(n, len(levels) - 1) + 1):
                carry = levels[v]
                for i in range(len(slices)):
                    if not carry:
                        break
                    slices[i], carry = slices[i] ^ carry, slices[i] & carry
                if carry:
                    slices.append(carry)
        if not slices:
            return []
        live = self._live
        exactly: dict[int, int] = {}
        for m in range(1, signature.complexity + 1):
            if m >> len(slices):
                break
            members = live
            for i, part in enumerate(slices):
                members &= part if (m >> i) & 1 else ~part
                if not members:
                    break
            if members:
                exactly[m] = members
        d_cue = signature.complexity
        buckets = sorted(
            (m / (d_cue + d - m), m, d) for m in exactly for d in self._by_complexity if d >= m
        )
        found: list[tuple[NamedNode, float]] = []
        for similarity, m, d in reversed(buckets):
            members = exactly[m] & self._by_complexity[d]
            for cls in self._members(members):
                found.append((cls, similarity))
                if len(found) >= limit:
                    return found
        return found
