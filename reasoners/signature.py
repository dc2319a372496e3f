"""Scene signatures: for each (signature property, leaf class) the number of distinct objects.

A learned class carries the signature of the scene it was learned from as
``C ≡ ⊓ (≥n p.T)``; a scene belongs to C when its signature meets every restriction.

>>> from ontologies.vocab import PLANE, SPHERE, engram
>>> one = Signature({(engram("sphereIsAboveOf"), PLANE): 1, (engram("planeIsBelowOf"), SPHERE): 1})
>>> two = Signature({(engram("sphereIsAboveOf"), PLANE): 1, (engram("planeIsBelowOf"), SPHERE): 2})
>>> two.satisfies(one), one.satisfies(two), two.complexity
(True, False, 3)
>>> Signature.from_json(two.to_json()) == two
True
"""

import functools
import json
from collections.abc import ItemsView, Iterator, Mapping, Sequence, ValuesView
from typing import cast

import numpy as np
from numpy.typing import NDArray
from pyoxigraph import NamedNode

from reasoners.errors import InvalidSceneError

__all__ = ["Key", "Signature"]

Key = tuple[NamedNode, NamedNode]
"""(signature property, leaf primitive class)."""


@functools.lru_cache(maxsize=8192)
def _named(iri: str) -> NamedNode:
    """One NamedNode per IRI: a memory of 10,000 classes reads ~300,000 IRIs of ~200 kinds."""
    return NamedNode(iri)


@functools.lru_cache(maxsize=8192)
def _key_order(key: Key) -> tuple[str, str]:
    return key[0].value, key[1].value


def _order(item: tuple[Key, int]) -> tuple[str, str]:
    """Signatures keep their keys sorted by IRI (reading ``.value`` makes a new string each
    time, so the few distinct keys' orders are cached)."""
    return _key_order(item[0])


_CHECKED = 16
"""How many of the hashes :func:`_frozenset_hashes` combines are compared with Python's."""


def _frozenset_hashes(item_hashes: "NDArray[np.int64]", ends: Sequence[int]) -> list[int] | None:
    """``hash(frozenset(items))`` of every run of items ending before ``ends[k]``, from the
    items' hashes, computed as CPython 3.11 combines them (Objects/setobject.c,
    ``frozenset_hash``: the entries' shuffled hashes xored, then mixed with the size), for all
    runs at once; None if a run is empty (the caller hashes them one by one). The caller checks
    a few against Python's own, so that another interpreter's algorithm is never trusted."""
    if not len(ends):
        return []
    bounds = np.array([0, *ends], dtype=np.intp)
    sizes = np.diff(bounds)
    if sizes.min() < 1 or bounds[-1] != len(item_hashes):
        return None
    h = item_hashes.view(np.uint64)
    shuffled = (h ^ np.uint64(89869747) ^ (h << np.uint64(16))) * np.uint64(3644798167)
    combined = np.bitwise_xor.reduceat(shuffled, bounds[:-1])
    combined ^= (sizes.astype(np.uint64) + np.uint64(1)) * np.uint64(1927868237)
    combined ^= (combined >> np.uint64(11)) ^ (combined >> np.uint64(25))
    combined = combined * np.uint64(69069) + np.uint64(907133923)
    combined[combined == np.uint64(2**64 - 1)] = np.uint64(590923713)  # -1 is reserved
    return cast(list[int], combined.view(np.int64).tolist())


class Signature(Mapping[Key, int]):
    """An immutable multiset of signature keys; hashable, so classes can be found by signature."""

    __slots__ = ("_counts", "_hash", "complexity")

    def __init__(self, counts: Mapping[Key, int]) -> None:
        self._set(counts, ordered=False)

    def _set(self, counts: Mapping[Key, int], *, ordered: bool) -> None:
        """Validate ``counts`` and keep them sorted by IRI (``ordered``: they already are)."""
        for key, n in counts.items():
            if isinstance(n, bool) or not isinstance(n, int) or n < 1:
                raise InvalidSceneError(
                    f"signature count of {key[0].value} on {key[1].value}: got {n!r}, "
                    "expected a positive integer"
                )
        self._counts: dict[Key, int] = (
            dict(counts) if ordered else dict(sorted(counts.items(), key=_order))
        )
        self._hash = hash(frozenset(self._counts.items()))
        self.complexity = sum(self._counts.values())
        """d: the sum of the counts."""

    def __getitem__(self, key: Key) -> int:
        return self._counts[key]

    def __iter__(self) -> Iterator[Key]:
        return iter(self._counts)

    def __len__(self) -> int:
        return len(self._counts)

    def items(self) -> ItemsView[Key, int]:
        return self._counts.items()  # the dict's own view, not Mapping's item by item lookups

    def values(self) -> ValuesView[int]:
        return self._counts.values()

    def __hash__(self) -> int:
        return self._hash

    def __eq__(self, other: object) -> bool:
        if isinstance(other, Signature):
            return self._hash == other._hash and self._counts == other._counts
        return NotImplemented

    def __repr__(self) -> str:
        inner = ", ".join(
            f"{p.value.rsplit('#', 1)[-1]} ≥{n} {t.value.rsplit('#', 1)[-1]}"
            for (p, t), n in self._counts.items()
        )
        return f"Signature({inner})"

    def satisfies(self, other: "Signature") -> bool:
        """True when these counts meet every restriction of ``other`` (self ∈ / ⊑ other)."""
        counts = self._counts
        return all(counts.get(key, 0) >= n for key, n in other._counts.items())

    def overlap(self, other: "Signature") -> int:
        """Σ min(self[k], other[k]): the size of the common part of the two multisets."""
        small, large = (self, other) if len(self) <= len(other) else (other, self)
        return sum(min(n, large._counts.get(key, 0)) for key, n in small._counts.items())

    def similarity(self, other: "Signature") -> float:
        """Weighted Jaccard similarity Σmin / Σmax, 1.0 for equal signatures."""
        common = self.overlap(other)
        union = self.complexity + other.complexity - common
        return common / union if union else 1.0

    def to_json(self) -> str:
        """``[[property IRI, leaf IRI, n], ...]``, sorted; :meth:`from_json` reads it back."""
        return json.dumps([[p.value, t.value, n] for (p, t), n in self._counts.items()])

    @classmethod
    def trusted(cls, counts: dict[Key, int]) -> "Signature":
        """A signature that takes ``counts`` as they are (not copied), already in signature
        order (as :meth:`items` gives them), such as a saved index file holds; the counts are
        still checked."""
        if not all(type(n) is int and n > 0 for n in counts.values()):
            signature = cls.__new__(cls)
            signature._set(counts, ordered=True)  # raises, naming the bad count
        signature = cls.__new__(cls)
        signature._counts = counts
        signature._hash = hash(frozenset(counts.items()))
        signature.complexity = sum(counts.values())
        return signature

    @classmethod
    def unchecked_runs(
        cls,
        keys: Sequence[Key],
        counts: Sequence[int],
        ends: Sequence[int],
        item_hashes: "NDArray[np.int64] | None" = None,
    ) -> list["Signature"]:
        """The signatures laid end to end in ``keys`` and ``counts`` (each one's keys in
        signature order), the k-th ending before ``ends[k]``; the counts are taken as they are,
        not checked: for counts checked in bulk, as a saved index file's are
        (:mod:`reasoners.index_file`). One loop for them all, 100,000 at a time.

        ``item_hashes[i]``, when given, is ``hash((keys[i], counts[i]))``: the signatures'
        hashes are then combined from them in numpy (:func:`_frozenset_hashes`) instead of
        building a frozenset per signature, and checked against Python's on the first few.
        """
        hashes = None if item_hashes is None else _frozenset_hashes(item_hashes, ends)
        made: list[Signature] = []
        append, new, start = made.append, cls.__new__, 0
        for k, end in enumerate(ends):
            run = counts[start:end]
            counts_of = dict(zip(keys[start:end], run, strict=True))
            signature = new(cls)
            signature._counts = counts_of
            signature._hash = hash(frozenset(counts_of.items())) if hashes is None else hashes[k]
            signature.complexity = sum(run)
            append(signature)
            start = end
        if hashes is not None and any(
            s._hash != hash(frozenset(s._counts.items())) for s in made[:_CHECKED]
        ):  # another Python's frozenset hash: every signature hashed as it is built
            for signature in made:
                signature._hash = hash(frozenset(signature._counts.items()))
        return made

    @classmethod
    def from_json(cls, text: str) -> "Signature":
        """The signature written by :meth:`to_json`; ``InvalidSceneError`` if malformed."""
        try:
            rows = json.loads(text)
            counts = {(_named(p), _named(t)): n for p, t, n in rows}
            pairs = [(p, t) for p, t, _ in rows]
        except (ValueError, TypeError) as error:
            raise InvalidSceneError(f"signature JSON: got {text[:80]!r}: {error}") from None
        signature = cls.__new__(cls)
        # to_json writes the keys in order: then only strings are compared, no IRIs read back
        signature._set(counts, ordered=len(counts) == len(pairs) and pairs == sorted(pairs))
        return signature
