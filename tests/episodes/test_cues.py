"""Queries by cue: first / last / n-th time, all, between, how many; one SPARQL query each."""

import datetime as dt
from collections.abc import Callable
from typing import Any

import pytest

from episodes import ArgumentSpec, Cue, EpisodeMemory, InvalidInputError, NotFoundError

HISTORY = [
    # (id, activity, agent, object, begin, end)
    (
        "b1",
        "babbling",
        "HyungJin",
        "left hand",
        "2025-12-01T10:00:00+00:00",
        "2025-12-01T10:05:00+00:00",
    ),
    (
        "b2",
        "babbling",
        "Maxime",
        "left hand",
        "2026-01-10T09:00:00+00:00",
        "2026-01-10T09:10:00+00:00",
    ),
    (
        "b3",
        "babbling",
        "HyungJin",
        "right hand",
        "2026-01-26T15:30:00+00:00",
        "2026-01-26T15:40:00+00:00",
    ),
    (
        "b4",
        "babbling",
        "HyungJin",
        "left hand",
        "2026-02-25T08:00:00+00:00",
        "2026-02-25T08:30:00+00:00",
    ),
    ("p1", "point", "Maxime", "ball", "2026-01-26T15:35:00+00:00", None),
]
NOW = dt.datetime(2026, 2, 26, 10, 0, tzinfo=dt.UTC)


@pytest.fixture
def history(memory: EpisodeMemory) -> EpisodeMemory:
    for episode_id, activity, agent, obj, begin, end in HISTORY:
        arguments = [ArgumentSpec("agent", agent), ArgumentSpec("object", obj)]
        memory.begin(activity, arguments=arguments, begin=begin, episode_id=episode_id)
        if end:
            memory.end(episode_id, end=end)
    return memory


def queries_run(memory: EpisodeMemory, call: Callable[[], Any]) -> tuple[Any, int]:
    seen: list[str] = []
    with memory.store.tracing(lambda kind, text, bindings: seen.append(kind)):
        result = call()
    return result, seen.count("query")


@pytest.mark.parametrize(
    ("which", "n", "agent", "obj", "expected"),
    [
        ("first", 1, None, None, "b1"),
        ("last", 1, None, None, "b4"),
        ("nth", 2, None, None, "b2"),
        ("nth", 3, None, None, "b3"),
        ("first", 1, "Maxime", None, "b2"),
        ("last", 1, "HyungJin", "right hand", "b3"),
        ("nth", 2, "HyungJin", None, "b3"),
        ("last", 1, None, "left hand", "b4"),
    ],
)
def test_recall_finds_the_first_last_and_nth_time_in_one_query(
    history: EpisodeMemory, which: str, n: int, agent: str | None, obj: str | None, expected: str
) -> None:
    cue = Cue("babbling", agent=agent, obj=obj)
    found, queries = queries_run(history, lambda: history.recall(cue, which=which, n=n))  # type: ignore[arg-type]
    assert found.episode.id == expected
    # the ordered ids of the matches; the answer's summary is read from the store's indexes
    # (episodes/summaries.py): gathering every match's participants in the query was linear
    # in the matches, and SPARQL cannot bind OFFSET
    assert queries == 1


def test_recall_says_when_it_was(history: EpisodeMemory) -> None:
    found = history.recall(Cue("babbling", agent="HyungJin", obj="right hand"), which="last")
    assert found.when == "one month ago, on January 26th"
    assert found.episode.participants == ("HyungJin", "right hand")
    assert history.recall(Cue("babbling"), which="last").when == "yesterday at 08:00"


def test_no_matching_episode_is_not_found_naming_the_cue(history: EpisodeMemory) -> None:
    with pytest.raises(NotFoundError, match="Maxime"):
        history.recall(Cue("babbling", agent="Maxime"), which="nth", n=2)
    with pytest.raises(NotFoundError):
        history.recall(Cue("juggling"), which="first")


@pytest.mark.parametrize(
    ("options", "field"),
    [({"which": "nth", "n": 0}, "n"), ({"which": "middle"}, "which"), ({"n": True}, "n")],
)
def test_bad_recall_arguments_name_the_field(
    history: EpisodeMemory, options: dict, field: str
) -> None:
    with pytest.raises(InvalidInputError) as caught:
        history.recall(Cue("babbling"), **options)
    assert caught.value.field == field


def test_all_episodes_of_an_activity_oldest_first_in_one_query(history: EpisodeMemory) -> None:
    found, queries = queries_run(history, lambda: history.all(Cue("babbling", agent="HyungJin")))
    assert [r.episode.id for r in found] == ["b1", "b3", "b4"]
    assert queries == 1  # the role matches; their summaries come from pattern lookups


def test_how_many_times_in_one_query(history: EpisodeMemory) -> None:
    count, queries = queries_run(history, lambda: history.count(Cue("babbling")))
    assert (count, queries) == (4, 1)
    assert history.count(Cue("babbling", agent="HyungJin", obj="left hand")) == 2
    assert history.count(Cue("babbling", agent="Nobody")) == 0


def test_what_happened_between_two_times(history: EpisodeMemory) -> None:
    found, queries = queries_run(
        history,
        lambda: history.between("2026-01-26T15:38:00+00:00", "2026-01-26T16:00:00+00:00"),
    )
    # b3 runs until 15:40; p1 began 15:35 and has not ended
    assert [r.episode.id for r in found] == ["b3", "p1"]
    assert queries == 1  # the window's episodes; their summaries come from pattern lookups
    assert history.between("2026-01-01T00:00:00+00:00", "2026-01-02T00:00:00+00:00") == []


def test_times_in_other_zones_compare_as_instants(history: EpisodeMemory) -> None:
    found = history.between("2026-01-26T16:38:00+01:00", "2026-01-26T16:39:00+01:00")
    assert [r.episode.id for r in found] == ["b3", "p1"]


@pytest.mark.parametrize(
    ("start", "end", "field"),
    [
        ("2026-01-26T16:00:00", "2026-01-27T00:00:00+00:00", "start"),
        ("2026-01-27T00:00:00+00:00", "2026-01-26T00:00:00+00:00", "end"),
    ],
)
def test_bad_window_names_the_field(
    history: EpisodeMemory, start: str, end: str, field: str
) -> None:
    with pytest.raises(InvalidInputError) as caught:
        history.between(start, end)
    assert caught.value.field == field


def test_knowledge_consolidated_from_the_episodes(history: EpisodeMemory) -> None:
    (babbling,) = history.knowledge("babbling")
    assert babbling.episodes == 4
    assert babbling.first == dt.datetime(2025, 12, 1, 10, 0, tzinfo=dt.UTC)
    assert babbling.last == dt.datetime(2026, 2, 25, 8, 0, tzinfo=dt.UTC)
    assert [(p.role, p.name, p.times) for p in babbling.participants[:2]] == [
        ("agent", "HyungJin", 3),
        ("object", "left hand", 3),
    ]
    assert [k.activity for k in history.knowledge()] == ["babbling", "point"]


def test_arguments_stored_before_the_cue_index_are_found_once_a_memory_opens(
    history: EpisodeMemory,
) -> None:
    """A store written before cue keys existed: the keys are added when a memory opens it."""
    from episodes.cue_index import CUE_KEY
    from ontologies.vocab import EPISODES

    store = history.store
    with store.transaction() as tx:
        for quad in list(store.quads(predicate=CUE_KEY)):
            tx.delete(quad.subject, CUE_KEY, quad.object, EPISODES)  # type: ignore[arg-type]
    assert history.count(Cue("babbling", agent="HyungJin")) == 0  # the index is empty
    reopened = EpisodeMemory(store, clock=lambda: NOW)
    assert reopened.count(Cue("babbling", agent="HyungJin")) == 3
    assert reopened.recall(Cue("babbling", obj="right hand"), which="last").episode.id == "b3"


def test_a_retracted_argument_leaves_the_cue_index(history: EpisodeMemory) -> None:
    history.remove_argument("b4", role="agent", value="HyungJin")
    assert history.count(Cue("babbling", agent="HyungJin")) == 2
    assert history.count(Cue("babbling", participant="HyungJin")) == 2
    history.add_argument("b4", role="recipient", value="HyungJin")
    assert history.count(Cue("babbling", agent="HyungJin")) == 2
    assert history.count(Cue("babbling", participant="HyungJin")) == 3
    assert history.count(Cue("babbling", role="recipient")) == 1


def test_the_nth_time_reads_only_the_first_matches_it_needs(memory: EpisodeMemory) -> None:
    from episodes.cues import _kind

    for k in range(12):
        memory.begin(
            "waving",
            arguments=[ArgumentSpec("agent", "Anna" if k % 2 else "Peter")],
            begin=f"2026-01-{k + 1:02d}T10:00:00+00:00",
            episode_id=f"w{k + 1}",
        )
    assert memory.recall(Cue("waving"), which="nth", n=10).episode.id == "w10"
    assert memory.recall(Cue("waving"), which="nth", n=11).episode.id == "w11"
    assert memory.recall(Cue("waving", agent="Anna"), which="nth", n=6).episode.id == "w12"
    with pytest.raises(NotFoundError):
        memory.recall(Cue("waving"), which="nth", n=13)
    assert [_kind("nth", n) for n in (1, 10, 11, 100, 101, 1000, 1001)] == [
        "head10",
        "head10",
        "head100",
        "head100",
        "head1000",
        "head1000",
        "list",
    ]
