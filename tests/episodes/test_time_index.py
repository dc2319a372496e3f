"""The time index (episodes/time_index.py): day buckets for "what happened between" and the
first / last pointers of each activity answer exactly as the queries that read every episode,
through ends, deletions, imports and stores written before the index."""

import datetime as dt

from hypothesis import given, settings
from hypothesis import strategies as st

from episodes import ArgumentSpec, Cue, EpisodeMemory, lifecycle
from episodes.terms import episode_id_of
from episodes.time_index import CUE_DAY, FIRST_OF, LAST_OF
from kg import Store
from ontologies.vocab import EPISODES

NOW = dt.datetime(2026, 2, 26, 10, 0, tzinfo=dt.UTC)
ORIGIN = dt.datetime(2026, 1, 1, tzinfo=dt.UTC)
ZONES = (dt.UTC, dt.timezone(dt.timedelta(hours=2)), dt.timezone(dt.timedelta(hours=-7)))
ACTIVITIES = ("babbling", "point")

episode_specs = st.lists(
    st.tuples(
        st.integers(0, 30 * 24 * 60),  # begin, minutes after ORIGIN
        st.none() | st.integers(0, 5 * 24 * 60),  # duration in minutes, None: running
        st.sampled_from(ACTIVITIES),
        st.sampled_from(ZONES),
        st.booleans(),  # ended later (a running one), or deleted later (an ended one)
    ),
    max_size=12,
)
windows = st.lists(
    st.tuples(
        st.integers(-2 * 24 * 60, 40 * 24 * 60),
        st.integers(0, 70 * 24 * 60),  # past 62 days: the plain filter
        st.sampled_from(ZONES),
    ),
    min_size=1,
    max_size=4,
)


def at(minutes: int, zone: dt.tzinfo) -> dt.datetime:
    return (ORIGIN + dt.timedelta(minutes=minutes)).astimezone(zone)


def build(specs: list[tuple[int, int | None, str, dt.tzinfo, bool]]) -> EpisodeMemory:
    memory = EpisodeMemory(Store(), clock=lambda: NOW)
    for k, (begin, duration, activity, zone, later) in enumerate(specs):
        end = None if duration is None or (later and duration is not None and k % 2) else duration
        lifecycle.begin_episode(
            memory.store,
            activity=activity,
            arguments=[ArgumentSpec("agent", f"p{k % 3}")],
            begin=at(begin, zone),
            end=at(begin + end, zone) if end is not None else None,
            episode_id=f"e{k}",
            snapshots=False,
        )
    for k, (begin, duration, _, zone, later) in enumerate(specs):
        if later and duration is not None and k % 2:
            lifecycle.end_episode(memory.store, f"e{k}", end=at(begin + duration, zone))
        elif later and duration is not None:
            memory.delete(f"e{k}")
    return memory


def old_between(memory: EpisodeMemory, start: dt.datetime, end: dt.datetime) -> list[str]:
    """The query before the index: every begin time filtered, every end looked up."""
    from episodes.times import to_literal

    rows = memory.store.select(
        "episodes_between", **{"from": to_literal(start), "to": to_literal(end)}
    )
    return [episode_id_of(r["episode"]) for r in rows]  # type: ignore[arg-type]


def old_end(memory: EpisodeMemory, activity: str, which: str) -> str | None:
    from pyoxigraph import Literal

    rows = memory.store.select(f"episodes_activity_{which}2", activity=Literal(activity))
    return episode_id_of(rows[0]["episode"]) if rows else None  # type: ignore[arg-type]


def answers(memory: EpisodeMemory, activity: str, which: str) -> str | None:
    found = memory.count(Cue(activity))
    if not found:
        return None
    return memory.recall(Cue(activity), which=which).episode.id  # type: ignore[arg-type]


@settings(max_examples=60, deadline=None)
@given(episode_specs, windows)
def test_index_answers_as_the_queries_over_every_episode(
    specs: list[tuple[int, int | None, str, dt.tzinfo, bool]],
    window_list: list[tuple[int, int, dt.tzinfo]],
) -> None:
    memory = build(specs)
    for start, length, zone in window_list:
        window = (at(start, zone), at(start + length, zone))
        got = [r.episode.id for r in memory.between(*window)]
        assert got == old_between(memory, *window)
    for activity in ACTIVITIES:
        for which in ("first", "last"):
            assert answers(memory, activity, which) == old_end(memory, activity, which)


def test_a_recent_window_finds_the_running_episode_and_a_long_one(memory: EpisodeMemory) -> None:
    lifecycle.begin_episode(
        memory.store,
        activity="walk",
        begin=ORIGIN,
        episode_id="long",
        end=ORIGIN + dt.timedelta(days=20),
        snapshots=False,
    )
    lifecycle.begin_episode(
        memory.store, activity="walk", begin=ORIGIN, episode_id="open", snapshots=False
    )
    lifecycle.begin_episode(
        memory.store,
        activity="walk",
        begin=ORIGIN,
        episode_id="short",
        end=ORIGIN + dt.timedelta(hours=1),
        snapshots=False,
    )
    window = (ORIGIN + dt.timedelta(days=10), ORIGIN + dt.timedelta(days=10, hours=1))
    assert [r.episode.id for r in memory.between(*window)] == ["long", "open"]
    lifecycle.end_episode(memory.store, "open", end=ORIGIN + dt.timedelta(days=2))
    assert [r.episode.id for r in memory.between(*window)] == ["long"]
    assert len(list(memory.store.quads(None, CUE_DAY, None, EPISODES))) == 21 + 3 + 1


def test_deleting_the_last_episode_points_at_the_one_before(memory: EpisodeMemory) -> None:
    for k in range(3):
        lifecycle.begin_episode(
            memory.store,
            activity="give",
            episode_id=f"g{k}",
            begin=ORIGIN + dt.timedelta(hours=k),
            snapshots=False,
        )
    assert memory.recall(Cue("give"), which="last").episode.id == "g2"
    memory.delete("g2")
    memory.delete("g0")
    assert memory.recall(Cue("give"), which="last").episode.id == "g1"
    assert memory.recall(Cue("give"), which="first").episode.id == "g1"
    memory.delete("g1")
    assert memory.count(Cue("give")) == 0
    assert not list(memory.store.quads(None, LAST_OF, None, EPISODES))


def test_a_store_written_before_the_index_is_indexed_when_a_memory_opens(
    memory: EpisodeMemory,
) -> None:
    for k in range(4):
        lifecycle.begin_episode(
            memory.store,
            activity="take",
            episode_id=f"t{k}",
            begin=ORIGIN + dt.timedelta(days=k),
            snapshots=False,
            end=ORIGIN + dt.timedelta(days=k, hours=1) if k < 3 else None,
        )
    store = memory.store
    with store.transaction() as tx:
        for predicate in (CUE_DAY, FIRST_OF, LAST_OF):
            tx.delete_matching(None, predicate, None, graph=EPISODES)
    reopened = EpisodeMemory(store, clock=lambda: NOW)
    window = (ORIGIN + dt.timedelta(days=1), ORIGIN + dt.timedelta(days=3, minutes=1))
    assert [r.episode.id for r in reopened.between(*window)] == ["t1", "t2", "t3"]
    assert reopened.recall(Cue("take"), which="last").episode.id == "t3"
    assert reopened.recall(Cue("take"), which="first").episode.id == "t0"


def test_an_imported_episode_moves_the_pointers(memory: EpisodeMemory) -> None:
    lifecycle.begin_episode(
        memory.store, activity="give", episode_id="old", begin=ORIGIN, snapshots=False
    )
    exported = memory.export_rdf("old")
    other = EpisodeMemory(Store(), clock=lambda: NOW)
    lifecycle.begin_episode(
        other.store,
        activity="give",
        episode_id="new",
        snapshots=False,
        begin=ORIGIN + dt.timedelta(days=1),
    )
    other.import_rdf(exported)
    assert other.recall(Cue("give"), which="first").episode.id == "old"
    assert other.recall(Cue("give"), which="last").episode.id == "new"
    assert len(list(other.store.quads(None, LAST_OF, None, EPISODES))) == 1
