"""The time index: day buckets that let "what happened between" read only the episodes of the
window's days, and per-activity pointers to the first and the last episode, so that "the
first / last time <activity>" reads one row instead of sorting every episode of it.

Each episode carries one ``engram:cueDay`` literal per UTC day its time touches (``"2026-03-01"``),
``"running"`` while it has no end, or ``"long"`` if it touches more than
:data:`MAX_EPISODE_DAYS` days. An episode overlaps a window only if some instant of the
window is in it, and that instant's day is one of the window's days: the episodes of the
window's days (and the running and long ones) hold every answer, and the exact time filter runs on
those alone. The oldest episode of an activity carries ``engram:firstOfActivity`` with the
activity's name, the newest ``engram:lastOfActivity`` (ties broken by IRI as the queries'
``ORDER BY ?begin ?episode`` does). Both are written with the episode, moved when it ends or
is deleted, in the same transaction; :func:`backfill` indexes episodes stored before.

>>> import datetime as dt
>>> t = dt.datetime(2026, 3, 1, 23, 30, tzinfo=dt.UTC)
>>> [d.value for d in day_literals(t, t + dt.timedelta(hours=1))]
['2026-03-01', '2026-03-02']
>>> [d.value for d in day_literals(t, None)]
['running']
"""

import datetime as dt
import operator

from pyoxigraph import Literal, NamedNode

from episodes import _rdf
from episodes.times import from_literal
from kg import Store, Transaction
from ontologies.vocab import EPISODES, PROV_STARTED_AT_TIME, engram

__all__ = [
    "CUE_DAY",
    "FIRST_OF",
    "LAST_OF",
    "LONG",
    "MAX_EPISODE_DAYS",
    "MAX_WINDOW_DAYS",
    "RUNNING",
    "backfill",
    "day_literals",
    "drop_activity_ends",
    "end_days",
    "refresh_activity",
    "window_days",
    "write_activity_ends",
    "write_days",
]

CUE_DAY = engram("cueDay")
FIRST_OF = engram("firstOfActivity")
LAST_OF = engram("lastOfActivity")
RUNNING = Literal("running")
LONG = Literal("long")
MAX_WINDOW_DAYS = 62
"""Windows of more days are answered by filtering every begin time (their answers are long)."""
MAX_EPISODE_DAYS = 366
"""An episode touching more days carries ``long`` in place of its days, and every window reads
the ``long`` ones (an episode of the years 1 to 9999 would otherwise write 3.6 million days)."""


def _span(start: dt.datetime, end: dt.datetime) -> tuple[dt.date, int]:
    """The first UTC day of ``start``..``end`` and how many days it touches."""
    first, last = start.astimezone(dt.UTC).date(), end.astimezone(dt.UTC).date()
    return first, (last - first).days + 1


def _days(start: dt.datetime, end: dt.datetime) -> list[Literal]:
    first, count = _span(start, end)
    return [Literal((first + dt.timedelta(days=i)).isoformat()) for i in range(count)]


def day_literals(begin: dt.datetime, end: dt.datetime | None) -> list[Literal]:
    """The ``engram:cueDay`` values of an episode of ``begin``..``end`` (``None``: running;
    ``long`` past :data:`MAX_EPISODE_DAYS`)."""
    if end is None:
        return [RUNNING]
    span = end.astimezone(dt.UTC).date() - begin.astimezone(dt.UTC).date()
    return [LONG] if span.days + 1 > MAX_EPISODE_DAYS else _days(begin, end)


def window_days(start: dt.datetime, end: dt.datetime) -> list[Literal] | None:
    """The day buckets a window must read (with ``running`` and ``long``), or ``None`` past
    :data:`MAX_WINDOW_DAYS` (counted before any day is built: a window of the years 1 to 9999
    holds 3.6 million days).

    >>> import datetime as dt
    >>> window_days(dt.datetime(1, 1, 1, tzinfo=dt.UTC), dt.datetime(9999, 1, 1, tzinfo=dt.UTC))
    """
    if _span(start, end)[1] > MAX_WINDOW_DAYS:
        return None
    return [*_days(start, end), RUNNING, LONG]


def write_days(
    tx: Transaction, episode: NamedNode, begin: dt.datetime, end: dt.datetime | None
) -> None:
    for day in day_literals(begin, end):
        tx.insert(episode, CUE_DAY, day, EPISODES)


def end_days(tx: Transaction, episode: NamedNode, begin: dt.datetime, end: dt.datetime) -> None:
    """A running episode ended: its days replace its ``running`` mark."""
    tx.delete(episode, CUE_DAY, RUNNING, EPISODES)
    write_days(tx, episode, begin, end)


def _holder(store: Store, pointer: NamedNode, activity: Literal) -> tuple[dt.datetime, str] | None:
    """The begin and IRI of the episode ``pointer`` marks for ``activity``: pattern lookups,
    not a SPARQL query (this runs twice in every begin)."""
    for marked in store.quads(None, pointer, activity, EPISODES):
        episode = marked.subject
        if not isinstance(episode, NamedNode):
            continue
        for began in store.quads(episode, PROV_STARTED_AT_TIME, None, EPISODES):
            return from_literal(began.object), episode.value
    return None


def write_activity_ends(
    tx: Transaction, store: Store, episode: NamedNode, activity: str, begin: dt.datetime
) -> None:
    """Point the activity's first / last at a new ``episode`` if it comes before / after the
    episodes stored. Call inside the transaction block (the write lock holds the reads)."""
    name = Literal(activity)
    key = (begin, episode.value)
    for pointer, beats in ((FIRST_OF, operator.lt), (LAST_OF, operator.gt)):
        held = _holder(store, pointer, name)
        if held is None or beats(key, held):
            if held is not None:
                tx.delete(NamedNode(held[1]), pointer, name, EPISODES)
            tx.insert(episode, pointer, name, EPISODES)


def drop_activity_ends(tx: Transaction, store: Store, episode: NamedNode) -> None:
    """``episode`` is being deleted in ``tx``: its pointers go to the next episode of its
    activity (its own triples are deleted with it)."""
    for pointer, order in ((FIRST_OF, "first"), (LAST_OF, "last")):
        for quad in store.quads(episode, pointer, None, EPISODES):
            name = quad.object
            assert isinstance(name, Literal)
            rows = store.select(f"episodes_activity_{order}2", activity=name)
            for row in rows:
                other = _rdf.iri(row, "episode")
                if other != episode:
                    tx.insert(other, pointer, name, EPISODES)
                    break


def refresh_activity(store: Store, activity: str) -> None:
    """Recompute the activity's first and last pointers from its episodes (after an import)."""
    name = Literal(activity)
    with store.transaction() as tx:
        for pointer, order in ((FIRST_OF, "first"), (LAST_OF, "last")):
            tx.delete_matching(None, pointer, name, graph=EPISODES)
            for row in store.select(f"episodes_activity_{order}2", activity=name)[:1]:
                tx.insert(_rdf.iri(row, "episode"), pointer, name, EPISODES)


def backfill(store: Store) -> int:
    """Index the episodes stored before the time index: their days, and the pointers of the
    activities that have none; how many episodes and activities."""
    rows = store.select("episodes_days_unindexed")
    if rows:
        with store.transaction() as tx:
            for row in rows:
                write_days(
                    tx, _rdf.iri(row, "episode"), _rdf.time(row, "begin"), _rdf.opt_time(row, "end")
                )
    activities = [_rdf.text(r, "activity") for r in store.select("episodes_activity_unpointed")]
    for activity in activities:
        refresh_activity(store, activity)
    return len(rows) + len(activities)
