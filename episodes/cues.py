"""Queries by cue, each one SPARQL query from ``sparql/``, answered with times in words.

"The first / last / n-th time <agent> did <activity> (with <object>)", "all episodes of
<activity>", "what happened between T1 and T2", "how many times".
"""

import datetime as dt
from typing import Literal as Which
from urllib.parse import unquote

from pyoxigraph import Literal, NamedNode

from episodes import _rdf
from episodes.cue_index import cue_key
from episodes.errors import InvalidInputError, NotFoundError
from episodes.model import EpisodeSummary, Recollection
from episodes.summaries import read_summaries
from episodes.terms import check_name, episode_id_of, participant_iri, role_iri
from episodes.time_index import window_days
from episodes.times import parse_time, say_when, to_literal
from kg import Store

__all__ = ["Cue", "all_episodes", "count_episodes", "happened_between", "matching", "recall"]

MAX_N = 1_000_000


class Cue:
    """What a question names: an activity, and who or what took part in which role.

    ``agent`` is the participant in the role ``agent`` (the paper's ``role='agent'``: in
    "Maxime pointed to HyungJin", HyungJin is the ``recipient``, not the agent); ``obj`` the
    one in the role ``object``; ``participant`` one in ``role``, or in any role when ``role``
    is not given; ``role`` alone asks for episodes with someone in that role. Arguments added
    after the fact count; removed or replaced ones do not.

    >>> sorted(Cue("babbling", agent="HyungJin").bindings())
    ['activity', 'agent']
    >>> str(Cue("pointing", role="recipient", participant="HyungJin"))
    "activity 'pointing', recipient 'HyungJin'"
    """

    def __init__(
        self,
        activity: str,
        *,
        agent: str | None = None,
        obj: str | None = None,
        role: str | None = None,
        participant: str | None = None,
    ):
        self.activity = check_name(activity, "activity")
        self.agent = participant_iri(agent, "agent") if agent is not None else None
        self.obj = participant_iri(obj, "object") if obj is not None else None
        self.role = role_iri(role, "role") if role is not None else None
        self.participant = (
            participant_iri(participant, "participant") if participant is not None else None
        )

    def bindings(self) -> dict[str, NamedNode | Literal]:
        bound: dict[str, NamedNode | Literal] = {"activity": Literal(self.activity)}
        for name, term in (
            ("agent", self.agent),
            ("object", self.obj),
            ("role", self.role),
            ("participant", self.participant),
        ):
            if term is not None:
                bound[name] = term
        return bound

    def constraints(self) -> list[tuple[NamedNode | None, NamedNode | None]]:
        """The cue's role constraints: (role, participant) pairs, either may be ``None``."""
        pairs: list[tuple[NamedNode | None, NamedNode | None]] = []
        if self.agent is not None:
            pairs.append((AGENT_ROLE, self.agent))
        if self.obj is not None:
            pairs.append((OBJECT_ROLE, self.obj))
        if self.role is not None or self.participant is not None:
            pairs.append((self.role, self.participant))
        return pairs

    def query(self, kind: str = "list") -> tuple[str, dict[str, NamedNode | Literal]]:
        """The name of the ``sparql/`` query of ``kind`` (``list``, ``first``, ``last`` or
        ``count``) for this cue, and its bindings: the activity, or one cue index key per role
        constraint (see :mod:`episodes.cue_index`)."""
        pairs = self.constraints()
        bound: dict[str, NamedNode | Literal] = {"activity": Literal(self.activity)}
        for i, (role, who) in enumerate(pairs, start=1):
            bound[f"key{i}"] = cue_key(self.activity, role, who)
        if kind not in ("list", "first", "last", "count", *(f"head{n}" for n in HEADS)):
            raise InvalidInputError("kind", kind, "'list', 'first', 'last' or 'count'")
        return f"episodes_cue_{kind}_{len(pairs)}", bound

    def __str__(self) -> str:
        words = [f"activity {self.activity!r}"]
        if self.agent is not None:
            words.append(f"agent {_name(self.agent)!r}")
        if self.obj is not None:
            words.append(f"object {_name(self.obj)!r}")
        if self.participant is not None:
            role = _name(self.role) if self.role is not None else "participant"
            words.append(f"{role} {_name(self.participant)!r}")
        elif self.role is not None:
            words.append(f"someone as {_name(self.role)!r}")
        return ", ".join(words)

    def phrase(self) -> str:
        """What the cue says happened, in words: "HyungJin did pointing with the ball"."""
        words: list[str] = []
        if self.agent is not None:
            words.append(f"{_name(self.agent)} did {self.activity}")
        elif self.participant is not None and self.role is not None:
            words.append(f"{_name(self.participant)} was the {_name(self.role)} of {self.activity}")
        elif self.participant is not None:
            words.append(f"{_name(self.participant)} took part in {self.activity}")
        else:
            words.append(f"{self.activity} happened")
        if self.obj is not None:
            words.append(f"with {_name(self.obj)}")
        if self.agent is not None and self.participant is not None:
            role = f"as {_name(self.role)}" if self.role is not None else "taking part"
            words.append(f"({_name(self.participant)} {role})")
        elif self.role is not None and self.participant is None:
            words.append(f"(with someone as {_name(self.role)})")
        return " ".join(words)


def said(cue: Cue, which: str, n: int, when: str) -> str:
    """The answer to a recall in words."""
    ordinal = {"first": "first", "last": "last"}.get(which, _ordinal(n))
    return f"The {ordinal} time {cue.phrase()} was {when}."


def _ordinal(n: int) -> str:
    suffix = "th" if 10 <= n % 100 <= 20 else {1: "st", 2: "nd", 3: "rd"}.get(n % 10, "th")
    return f"{n}{suffix}"


def _name(term: NamedNode) -> str:
    return unquote(term.value.rsplit("/", 1)[-1])


AGENT_ROLE = role_iri("agent")
OBJECT_ROLE = role_iri("object")


def matching(store: Store, cue: Cue, kind: str = "list") -> list[NamedNode]:
    """The episodes matching ``cue``, oldest first (one query); ``kind`` ``first`` or ``last``
    for only that one."""
    name, bound = cue.query(kind)
    rows = store.select(name, **bound)
    if not rows and name in ("episodes_cue_first_0", "episodes_cue_last_0"):
        # a store no writer has indexed yet (read-only): sort the activity's episodes
        rows = store.select(f"episodes_activity_{kind}2", **bound)[:1]
    return [_rdf.iri(row, "episode") for row in rows]


def _summary(row: _rdf.Row) -> EpisodeSummary:
    return EpisodeSummary(
        id=episode_id_of(_rdf.iri(row, "episode")),
        activity=_rdf.text(row, "activity"),
        activity_type=_rdf.opt_text(row, "type"),
        begin=_rdf.time(row, "begin"),
        end=_rdf.opt_time(row, "end"),
        participants=_rdf.names(row),
    )


def recall(
    store: Store, cue: Cue, *, which: Which["first", "last", "nth"], n: int = 1, now: dt.datetime
) -> Recollection:
    """The first, last or ``n``-th (1 is the first) episode matching ``cue``, and when it was.

    Raises :class:`InvalidInputError` for a bad ``which`` or ``n`` and :class:`NotFoundError`
    when fewer episodes match.
    """
    if which not in ("first", "last", "nth"):
        raise InvalidInputError("which", which, "'first', 'last' or 'nth'")
    if isinstance(n, bool) or not isinstance(n, int) or not 1 <= n <= MAX_N:
        raise InvalidInputError("n", n, f"an integer from 1 to {MAX_N}")
    found = matching(store, cue, _kind(which, n))
    picked = found[n - 1 : n] if which == "nth" else found
    summaries = read_summaries(store, picked)  # then the answer's summary
    if not summaries:
        ordinal = {"first": "a first", "last": "a last"}.get(which, f"a time number {n}")
        raise NotFoundError(f"cue: no episode matches {cue} ({ordinal} was asked for)")
    summary = summaries[0]
    when = say_when(summary.begin, now)
    return Recollection(
        episode=summary,
        when=when,
        rank=n if which == "nth" else None,
        said=said(cue, which, n, when),
    )


HEADS = (10, 100, 1000)
"""The n-th time reads the first 10, 100 or 1,000 matches (``episodes_cue_head<N>_*``), the
smallest that holds it; beyond, all of them."""


def _kind(which: str, n: int) -> str:
    if which != "nth":
        return which
    return next((f"head{head}" for head in HEADS if n <= head), "list")


def all_episodes(store: Store, cue: Cue, *, now: dt.datetime) -> list[Recollection]:
    """Every episode matching ``cue``, oldest first, each with when it was."""
    if cue.constraints():  # the matching episodes by the cue index, then their summaries
        summaries = read_summaries(store, matching(store, cue))
    else:
        rows = store.select("episodes_of_activity", activity=Literal(cue.activity))
        summaries = [_summary(r) for r in rows]
    return [
        Recollection(episode=s, when=say_when(s.begin, now), rank=i)
        for i, s in enumerate(summaries, start=1)
    ]


def count_episodes(store: Store, cue: Cue) -> int:
    """How many episodes match ``cue``."""
    name, bound = cue.query("count")
    return _rdf.integer(store.select(name, **bound)[0], "count")


def happened_between(
    store: Store, start: dt.datetime | str, end: dt.datetime | str, *, now: dt.datetime
) -> list[Recollection]:
    """The episodes that overlap ``start``..``end``, oldest first, each with when it was.

    Raises :class:`InvalidInputError` for a bad time or a reversed window.
    """
    window_start, window_end = parse_time(start, "start"), parse_time(end, "end")
    if window_end < window_start:
        raise InvalidInputError(
            "end", window_end.isoformat(), f"a time not before start {window_start.isoformat()}"
        )
    times = {"from": to_literal(window_start), "to": to_literal(window_end)}
    days = window_days(window_start, window_end)
    if days is None:  # a long window: filter every begin time
        found = store.select("episodes_between", **times)
    else:  # the episodes of the window's day buckets (episodes/time_index.py)
        found = store.select_each("episodes_between_days", "day", days, **times)
    # prov:startedAtTime is also a run's: only episodes have a summary
    summaries = read_summaries(store, [_rdf.iri(r, "episode") for r in found])
    return [Recollection(episode=s, when=say_when(s.begin, now)) for s in summaries]
