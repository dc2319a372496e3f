"""What the scene memory's operations return (frozen dataclasses, named tuples: safe to share)."""

import datetime as dt
from dataclasses import dataclass
from typing import NamedTuple

from pyoxigraph import NamedNode

from reasoners.encode import Relation
from reasoners.signature import Signature

__all__ = [
    "ClassSummary",
    "ItemScores",
    "Match",
    "Recognition",
    "RetrievalResult",
    "SleepReport",
    "StoreResult",
]


class Recognition(NamedTuple):
    """The scene (or cue) belongs to ``cls``; ``confidence`` = d(cls) / d(scene).

    A named tuple rather than a dataclass: a scene in a large memory belongs to hundreds of
    classes, and every update builds all of them."""

    cls: NamedNode
    confidence: float
    complexity: int


@dataclass(frozen=True)
class Match:
    """A class and its weighted Jaccard similarity Σmin/Σmax to the cue, in (0, 1]."""

    cls: NamedNode
    similarity: float


@dataclass(frozen=True)
class ItemScores:
    """The raw terms of an item's score and what is derived from them on read."""

    iri: NamedNode
    kind: str
    """"class" (a learned scene class) or "item" (an experienced scene)."""
    complexity: int
    store_count: int
    retrieve_count: int
    raw_score: float
    """ζ now: derived for a class from its raw terms, its children and the maxima (the store's
    ``engram:score`` holds it as of the class's last update or the last sleep pass); computed
    for an item with the time decay."""
    normalised: float
    """ζ divided by the largest ζ of its kind: the best item is 1."""
    level: str
    """HIGH, LOW or WEAK, derived from ``normalised`` now."""
    stored_level: str | None
    """The level the last sleep pass wrote (None before the first pass)."""
    consecutive_weak: int
    pinned: bool
    created: dt.datetime
    last_accessed: dt.datetime
    cls: NamedNode | None = None
    """For an item: the class it was stored as."""


@dataclass(frozen=True)
class StoreResult:
    """What :meth:`SceneMemory.store_scene` did."""

    scene_item: NamedNode
    stored_as: NamedNode
    learned: bool
    """True when a new class was learned, False when the best recognised class was reinforced."""
    recognised: tuple[Recognition, ...]
    """The learned classes the scene belonged to before storing, by confidence."""
    confidence: float
    """Confidence of the best recognised class before storing (0 if none)."""
    signature: Signature
    relations: tuple[Relation, ...]
    parents: tuple[NamedNode, ...]
    """Direct parents of the stored class."""
    scores: ItemScores
    """Scores of the stored class after consolidating its branch."""


@dataclass(frozen=True)
class RetrievalResult:
    """What :meth:`SceneMemory.retrieve` found for a cue (the cue itself is never stored)."""

    signature: Signature
    exact: NamedNode | None
    generalisations: tuple[Recognition, ...]
    """Classes the cue belongs to (less specific), most specific first."""
    specialisations: tuple[Match, ...]
    """Classes that contain the cue (more specific), most similar first."""
    similar: tuple[Match, ...]
    """The most similar classes of the whole memory, best first."""
    recalled: NamedNode | None
    """The class returned: the exact match, else the most similar specialisation, else the most
    specific generalisation; its branch had its retrieve count raised."""
    branch: tuple[NamedNode, ...]
    activation: tuple[Match, ...] | None
    """With ``spread=True``: spreading activation from the recalled class over the graph."""


@dataclass(frozen=True)
class SleepReport:
    """What one sleep pass did."""

    at: dt.datetime
    rescored: int
    levels: dict[NamedNode, str]
    """Level of every live class after the pass."""
    item_levels: dict[NamedNode, str]
    forgotten_classes: tuple[NamedNode, ...]
    forgotten_items: tuple[NamedNode, ...]
    duration_s: float


@dataclass(frozen=True)
class ClassSummary:
    """A learned class as :meth:`MemoryReads.classes` lists it."""

    iri: NamedNode
    signature: Signature
    parents: tuple[NamedNode, ...]
    children: tuple[NamedNode, ...]
    items: int
    scores: ItemScores


@dataclass(frozen=True)
class ScoreTerms:
    """The terms of a class's semantic score ζ now, as DESIGN.md step 7 adds them up:
    ``ζ = a_d·d/max d + a_c·mean(ζ of direct children) + a_s·ln(1+s)/ln(1+max s)
    + a_r·ln(1+r)/ln(1+max r)``; ``normalised`` = ζ / ``max_zeta``."""

    complexity: int
    max_complexity: int
    store_count: int
    max_store: int
    retrieve_count: int
    max_retrieve: int
    children_zeta: tuple[float, ...]
    """ζ of each direct child."""
    weights: tuple[float, float, float, float]
    """(a_d, a_c, a_s, a_r)."""
    zeta: float
    max_zeta: float


@dataclass(frozen=True)
class TrashEntry:
    """Something in the trash: a class (with its signature) or an experienced scene (with its
    class), and when it was forgotten."""

    iri: NamedNode
    kind: str
    """"class" or "item"."""
    forgotten_at: dt.datetime
    signature: Signature | None = None
    cls: NamedNode | None = None
