"""Semantic knowledge consolidated from the episodes: per activity, how often it happened,
when first and last, and who and what usually took part in which role (what the ABM's
reasoning module kept in its knowledge tables, here derived by query, so never stale).
"""

import datetime as dt
from collections import defaultdict
from dataclasses import dataclass

from pyoxigraph import Literal, NamedNode

from episodes import _rdf
from episodes.terms import check_name
from kg import Store

__all__ = ["ActivityKnowledge", "Participation", "activity_knowledge"]


@dataclass(frozen=True)
class Participation:
    """Someone or something taking part in an activity in a role, and in how many episodes."""

    role: str
    name: str
    times: int


@dataclass(frozen=True)
class ActivityKnowledge:
    """What the memory knows about one activity."""

    activity: str
    episodes: int
    first: dt.datetime
    last: dt.datetime
    participants: tuple[Participation, ...]


def activity_knowledge(store: Store, activity: str | None = None) -> list[ActivityKnowledge]:
    """Knowledge about every activity, or about ``activity``; by activity name."""
    bindings: dict[str, NamedNode | Literal] = {}
    if activity is not None:
        bindings["activity"] = Literal(check_name(activity, "activity"))
    participants: dict[str, list[Participation]] = defaultdict(list)
    for row in store.select("episodes_activity_participants", **bindings):
        participants[_rdf.text(row, "activity")].append(
            Participation(
                role=_rdf.text(row, "role"),
                name=_rdf.text(row, "name"),
                times=_rdf.integer(row, "times"),
            )
        )
    return [
        ActivityKnowledge(
            activity=(name := _rdf.text(row, "activity")),
            episodes=_rdf.integer(row, "episodes"),
            first=_rdf.time(row, "first"),
            last=_rdf.time(row, "last"),
            participants=tuple(participants[name]),
        )
        for row in store.select("episodes_activity_summary", **bindings)
    ]
