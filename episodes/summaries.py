"""Episode summaries (activity, type, times, participants' labels) read straight from the
store's indexes: a few pattern lookups per episode instead of the ``episodes_summary`` query
and its grouping.

The answers are those of ``sparql/episodes_summary.rq`` (kept as the analyst's form and as
the reference of the test): an episode is a node typed ``engram:Episode`` with an activity
name and a begin; its participants are the labels of whoever it ``prov:wasAssociatedWith``
or ``prov:used``, distinct and sorted, over every graph (the store's default graph is their
union).
"""

from collections.abc import Sequence

from pyoxigraph import Literal, NamedNode

from episodes.model import EpisodeSummary
from episodes.terms import episode_id_of
from episodes.times import from_literal
from kg import Store
from ontologies.vocab import (
    ACTIVITY_NAME,
    ACTIVITY_TYPE,
    EPISODE,
    PROV_ENDED_AT_TIME,
    PROV_STARTED_AT_TIME,
    PROV_USED,
    PROV_WAS_ASSOCIATED_WITH,
    RDF_TYPE,
    RDFS_LABEL,
)

__all__ = ["read_summaries"]

_PARTICIPATION = (PROV_WAS_ASSOCIATED_WITH, PROV_USED)
_FIELDS = (ACTIVITY_NAME, ACTIVITY_TYPE, PROV_STARTED_AT_TIME, PROV_ENDED_AT_TIME)


def read_summaries(store: Store, episodes: Sequence[NamedNode]) -> list[EpisodeSummary]:
    """The summaries of ``episodes`` in their order, leaving out what is not an episode."""
    labels: dict[object, list[Literal]] = {}
    found: list[EpisodeSummary] = []
    for episode in episodes:
        fields: dict[NamedNode, object] = {}
        types: set[object] = set()
        who: list[object] = []
        for quad in store.quads(episode):
            predicate = quad.predicate
            if predicate in _PARTICIPATION:
                who.append(quad.object)
            elif predicate == RDF_TYPE:
                types.add(quad.object)
            elif predicate in _FIELDS:
                fields[predicate] = quad.object
        activity, begin = fields.get(ACTIVITY_NAME), fields.get(PROV_STARTED_AT_TIME)
        if EPISODE not in types or not isinstance(activity, Literal) or begin is None:
            continue
        terms: dict[Literal, None] = {}  # GROUP_CONCAT(DISTINCT ?label): distinct terms
        for participant in who:
            if participant not in labels:
                labels[participant] = [
                    q.object
                    for q in store.quads(participant, RDFS_LABEL)  # type: ignore[arg-type]
                    if isinstance(q.object, Literal)
                ]
            terms.update(dict.fromkeys(labels[participant]))
        joined = "\x1f".join(term.value for term in terms)
        kind, end = fields.get(ACTIVITY_TYPE), fields.get(PROV_ENDED_AT_TIME)
        found.append(
            EpisodeSummary(
                id=episode_id_of(episode),
                activity=activity.value,
                activity_type=kind.value if isinstance(kind, Literal) else None,
                begin=from_literal(begin),
                end=from_literal(end) if end is not None else None,
                participants=tuple(sorted(part for part in joined.split("\x1f") if part)),
            )
        )
    return found
