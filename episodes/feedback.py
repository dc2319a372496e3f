"""Feedback: people's 1-10 ratings of derived data, and the paper's ranking of candidates.

A candidate (an augmentation run, or one derived sample of it) is good enough when the first
quartile of its ratings is at least 6 and their median at least 7 (Petit, Fischer, Demiris
2016, section V-E). Among the good candidates, the best by median is compared with each other
one with a Wilcoxon signed-rank test over the ratings of the people who rated both; those not
significantly different from it are equivalent and kept as best too.

>>> stats = candidate_stats("a", [6, 7, 7, 8, 9])
>>> stats.q1, stats.median, stats.good
(7.0, 7.0, True)
"""

import datetime as dt
from collections import defaultdict
from collections.abc import Sequence
from dataclasses import dataclass
from urllib.parse import quote, unquote

import numpy as np
from pyoxigraph import Literal, NamedNode
from scipy.stats import wilcoxon

from episodes import _rdf
from episodes.augmentation import get_run, run_iri
from episodes.errors import EpisodeStateError, InvalidInputError, NotFoundError
from episodes.lifecycle import participant
from episodes.model import Rating
from episodes.terms import (
    check_id,
    check_name,
    episode_iri,
    new_id,
    part_iri,
    participant_iri,
)
from episodes.times import to_literal
from kg import Store
from ontologies.vocab import (
    EPISODE_NS,
    EPISODES,
    PROV_GENERATED_AT_TIME,
    PROV_PERSON,
    PROV_WAS_ATTRIBUTED_TO,
    PROV_WAS_REVISION_OF,
    QUESTION_NS,
    RATES,
    RATING,
    RATING_QUESTION,
    RATING_VALUE,
    RDF_TYPE,
)

__all__ = [
    "CandidateStats",
    "Comparison",
    "Ranking",
    "candidate_stats",
    "question_iri",
    "question_name",
    "rank",
    "rate",
]

Q1_THRESHOLD = 6.0
MEDIAN_THRESHOLD = 7.0


def rate(
    store: Store,
    episode_id: str,
    run_id: str,
    *,
    person: str,
    value: int,
    time: dt.datetime,
    sample: int | None = None,
    question: str | None = None,
    replace: bool = False,
) -> Rating:
    """Store ``person``'s rating (1-10) of a run, or of one of its derived samples, as the
    answer to ``question`` (a name or IRI; none by default).

    One person answers one question about one item once: a second answer raises
    :class:`EpisodeStateError` naming the first, unless ``replace`` is set, when it is stored
    as a revision of the first (``prov:wasRevisionOf``; the first is kept). Raises
    :class:`InvalidInputError` for a value outside 1..10 and :class:`NotFoundError` for an
    unknown episode, run or sample.
    """
    person = check_name(person, "person")
    if isinstance(value, bool) or not isinstance(value, int) or not 1 <= value <= 10:
        raise InvalidInputError("value", value, "an integer from 1 to 10")
    asked = question_iri(question) if question is not None else None
    rating_id = new_id()
    with store.transaction() as tx:
        run = get_run(store, episode_id, run_id)
        item = run_iri(episode_id, run_id)
        if sample is not None:
            if (
                isinstance(sample, bool)
                or not isinstance(sample, int)
                or not 0 <= sample < run.samples
            ):
                raise NotFoundError(f"sample: run {run_id!r} has no derived sample {sample!r}")
            item = part_iri(item, "sample", str(sample))
        bindings: dict[str, NamedNode | Literal] = {
            "item": item,
            "person": participant_iri(person, "person"),
        }
        if asked is not None:
            bindings["question"] = asked
        earlier = store.select("episodes_rating_current", **bindings)
        if earlier and not replace:
            raise EpisodeStateError(
                f"rating: {person!r} already rated {_item_id(item)!r}"
                + (f" for question {question!r}" if question is not None else "")
                + f" {_rdf.text(earlier[0], 'value')}; send replace=true to revise that answer"
            )
        node = part_iri(episode_iri(episode_id), "rating", rating_id)
        for row in earlier:
            tx.insert(node, PROV_WAS_REVISION_OF, _rdf.iri(row, "rating"), EPISODES)
        if asked is not None:
            tx.insert(node, RATING_QUESTION, asked, EPISODES)
        tx.insert(node, RDF_TYPE, RATING, EPISODES)
        tx.insert(node, RATES, item, EPISODES)
        tx.insert(node, RATING_VALUE, Literal(value), EPISODES)
        tx.insert(node, PROV_GENERATED_AT_TIME, to_literal(time), EPISODES)
        tx.insert(
            node, PROV_WAS_ATTRIBUTED_TO, participant(tx, person, PROV_PERSON, "person"), EPISODES
        )
    return Rating(
        id=rating_id,
        item=_item_id(item),
        person=person,
        value=value,
        time=time,
        question=None if asked is None else question_name(asked),
    )


def question_iri(question: str) -> NamedNode:
    """The IRI of a rating question: an IRI given as such, or one minted from its text."""
    text = check_name(question, "question")
    if text.startswith(("http://", "https://", "urn:")):
        return participant_iri(text, "question")
    return NamedNode(QUESTION_NS + quote(text, safe=""))


def question_name(iri: NamedNode) -> str:
    """The text a question IRI was minted from (or the IRI itself)."""
    return unquote(iri.value.removeprefix(QUESTION_NS))


def _item_id(item: NamedNode) -> str:
    """``<episode>/run/<run>[/sample/<i>]`` as a short id: ``<episode>/<run>[/<i>]``."""
    episode, _, rest = item.value.removeprefix(EPISODE_NS).partition("/run/")
    return f"{episode}/{rest.replace('/sample/', '/')}"


@dataclass(frozen=True)
class CandidateStats:
    """The ratings of one candidate and what the heuristic says about them."""

    item: str
    ratings: dict[str, int]
    n: int
    q1: float
    median: float
    mean: float
    good: bool


@dataclass(frozen=True)
class Comparison:
    """A Wilcoxon signed-rank test between the leader and another good candidate."""

    leader: str
    other: str
    pairs: int
    p_value: float
    equivalent: bool


@dataclass(frozen=True)
class Ranking:
    """Candidates best first; ``best`` holds the leader and the good candidates equivalent to it
    (empty if no candidate is good enough yet)."""

    candidates: tuple[CandidateStats, ...]
    best: tuple[str, ...]
    comparisons: tuple[Comparison, ...]
    leader: str | None


def candidate_stats(item: str, ratings: Sequence[int] | dict[str, int]) -> CandidateStats:
    """Quartiles and the verdict of the heuristic (Q1 >= 6 and median >= 7)."""
    by_person = (
        dict(ratings) if isinstance(ratings, dict) else {str(i): v for i, v in enumerate(ratings)}
    )
    values = np.array(list(by_person.values()), dtype=float)
    q1, median = (float(x) for x in np.percentile(values, [25, 50]))
    return CandidateStats(
        item=item,
        ratings=by_person,
        n=len(values),
        q1=q1,
        median=median,
        mean=float(values.mean()),
        good=q1 >= Q1_THRESHOLD and median >= MEDIAN_THRESHOLD,
    )


def compare(leader: CandidateStats, other: CandidateStats, alpha: float) -> Comparison:
    """Wilcoxon signed-rank test over the people who rated both (paired by person)."""
    people = sorted(leader.ratings.keys() & other.ratings.keys())
    a = np.array([leader.ratings[p] for p in people], dtype=float)
    b = np.array([other.ratings[p] for p in people], dtype=float)
    if not people:
        p_value = float("nan")  # nobody rated both: the test cannot tell them apart or not
    elif not np.any(a - b):
        p_value = 1.0  # identical ratings; scipy divides by zero here
    else:
        p_value = float(wilcoxon(a, b).pvalue)
    return Comparison(
        leader=leader.item,
        other=other.item,
        pairs=len(people),
        p_value=p_value,
        equivalent=bool(people) and p_value >= alpha,
    )


def rank(
    store: Store,
    augmentation: str,
    *,
    episode_id: str | None = None,
    alpha: float = 0.05,
    question: str | None = None,
) -> Ranking:
    """Rank the rated runs (and samples) of ``augmentation``, of one episode or of all, by the
    answers to ``question`` (the ratings given without a question when ``None``).

    Each person's current answer (the last revision) counts. Raises :class:`InvalidInputError`
    for a bad ``alpha``.
    """
    augmentation = check_name(augmentation, "augmentation")
    if isinstance(alpha, bool) or not isinstance(alpha, float | int) or not 0 < alpha < 1:
        raise InvalidInputError("alpha", alpha, "a significance level between 0 and 1")
    bindings: dict[str, NamedNode | Literal] = {"augmentation": Literal(augmentation)}
    if episode_id is not None:
        bindings["episode"] = episode_iri(check_id(episode_id, "episode"))
    if question is not None:
        bindings["question"] = question_iri(question)
    latest: dict[str, dict[str, tuple[dt.datetime, int]]] = defaultdict(dict)
    for row in store.select("episodes_ratings", **bindings):
        item = _item_id(_rdf.iri(row, "item"))
        person, value, time = (
            _rdf.text(row, "person"),
            _rdf.integer(row, "value"),
            _rdf.time(row, "time"),
        )
        if person not in latest[item] or latest[item][person][0] <= time:
            latest[item][person] = (time, value)
    stats = [
        candidate_stats(item, {p: v for p, (_, v) in people.items()})
        for item, people in latest.items()
    ]
    stats.sort(key=lambda s: (not s.good, -s.median, -s.q1, -s.mean, -s.n, s.item))
    leader = stats[0] if stats else None
    comparisons: list[Comparison] = []
    best: list[str] = []
    if leader is not None and leader.good:
        best.append(leader.item)
        for other in stats[1:]:
            if other.good:
                comparison = compare(leader, other, float(alpha))
                comparisons.append(comparison)
                if comparison.equivalent:
                    best.append(other.item)
    return Ranking(
        candidates=tuple(stats),
        best=tuple(best),
        comparisons=tuple(comparisons),
        leader=leader.item if leader else None,
    )
