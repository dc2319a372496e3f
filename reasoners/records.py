"""The records the in-memory model keeps: learned classes, experienced scenes, the trash.

:class:`ClassRecord` carries its score's raw terms and its place in the class graph as plain
fields (``z``, ``sums``, ``up``, ``fan_in``, ``mark``), so that the score table's refresh walks a
branch record to record without hashing IRIs.
"""

import datetime as dt
from dataclasses import dataclass, field

from pyoxigraph import NamedNode

from reasoners.signature import Signature

__all__ = ["ClassRecord", "ItemRecord", "TrashedClass", "TrashedItem"]


@dataclass
class ClassRecord:
    """A learned scene class: its signature, the raw terms of its score, and the ζ last
    written to the store (``score``, as of its last update; the live ζ is
    :meth:`reasoners.score_table.ScoreTable.zeta`)."""

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
    """Z_d, Z_s, Z_r in fixed point (``reasoners.score_table.SCALE``)."""
    sums: list[int] = field(default_factory=lambda: [0, 0, 0])
    """Σ Z_x over the direct children, in fixed point."""
    up: list["ClassRecord"] = field(default_factory=list, repr=False, compare=False)
    """The records of the direct parents (``ClassGraph.parents`` as records, so that
    :meth:`ScoreTable.refresh` walks a branch without hashing IRIs)."""
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
