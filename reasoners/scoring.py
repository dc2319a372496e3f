"""Consolidation formulas (DESIGN.md, "Scene memory: the algorithm", step 7) and levels.

Semantic score of class j::

    ζ = a_d·d/max d + a_c·mean(ζ of direct children)
        + a_s·ln(1+s)/ln(1+max s) + a_r·ln(1+r)/ln(1+max r)

Episodic score of an experienced scene e stored as class C: the same four terms, where the
complexity term is e's own (d(e)/max d over experienced scenes), the children term is C's
normalised semantic score (an experienced scene has no children; its class is the knowledge
it supports), the store and retrieve terms are C's; minus the decay
``o_t·ln(1 + (t_now - t_last)/τ)``; clipped to [0, 1]. Normalised scores divide by the largest
score, so the best item is 1.

>>> log_ratio(3, 3), log_ratio(0, 0)
(1.0, 0.0)
>>> level_of(0.2, high=0.6, weak=0.2), level_of(0.61, high=0.6, weak=0.2)
('LOW', 'HIGH')
"""

import math
from collections.abc import Iterable

from reasoners.policy import Policy

__all__ = [
    "HIGH",
    "LOW",
    "SCORE_DECIMALS",
    "WEAK",
    "episodic_score",
    "level_of",
    "log_ratio",
    "rounded",
    "semantic_score",
]

HIGH, LOW, WEAK = "HIGH", "LOW", "WEAK"
SCORE_DECIMALS = 6
"""Normalised scores are reported to this many decimals (the level uses the exact value)."""


def rounded(value: float) -> float:
    """``value`` to :data:`SCORE_DECIMALS` decimals as SPARQL's ``ROUND(x * 1e6) / 1e6`` gives
    it (halves away from zero), so the API and the analysts' query print the same number.

    >>> rounded(0.4472135955), rounded(0.0000005)
    (0.447214, 1e-06)
    """
    scaled = value * 10**SCORE_DECIMALS
    whole = math.floor(abs(scaled))
    if abs(scaled) - whole >= 0.5:
        whole += 1
    return float(math.copysign(whole, scaled) / 10**SCORE_DECIMALS)


def log_ratio(value: int, maximum: int) -> float:
    """ln(1 + value) / ln(1 + maximum), 0 when the maximum is 0."""
    if maximum <= 0:
        return 0.0
    return math.log1p(value) / math.log1p(maximum)


def semantic_score(
    policy: Policy,
    *,
    complexity: int,
    store_count: int,
    retrieve_count: int,
    children: Iterable[float],
    max_complexity: int,
    max_store: int,
    max_retrieve: int,
) -> float:
    """ζ of a learned class, in [0, 1] when the weights sum to at most 1."""
    scores = list(children)
    mean_children = sum(scores) / len(scores) if scores else 0.0
    return (
        policy.complexityWeight * (complexity / max_complexity if max_complexity else 0.0)
        + policy.childrenWeight * mean_children
        + policy.storeWeight * log_ratio(store_count, max_store)
        + policy.retrieveWeight * log_ratio(retrieve_count, max_retrieve)
    )


def episodic_score(
    policy: Policy,
    *,
    complexity_ratio: float,
    class_normalised: float,
    store_ratio: float,
    retrieve_ratio: float,
    age_s: float,
) -> float:
    """ζ of an experienced scene with the time decay, clipped to [0, 1]."""
    decay = policy.decayWeight * math.log1p(max(age_s, 0.0) / policy.decayTimeConstantSeconds)
    value = (
        policy.episodicComplexityWeight * complexity_ratio
        + policy.episodicChildrenWeight * class_normalised
        + policy.episodicStoreWeight * store_ratio
        + policy.episodicRetrieveWeight * retrieve_ratio
        - decay
    )
    return min(1.0, max(0.0, value))


def level_of(normalised: float, *, high: float, weak: float) -> str:
    """HIGH above ``high``, WEAK below ``weak``, LOW in between (both bounds included)."""
    if normalised > high:
        return HIGH
    if normalised < weak:
        return WEAK
    return LOW
