"""The episode timeline's pages (api/views/timeline.py): the same entries as the episode memory
reads one by one, oldest first, and a page costs a fixed number of queries whatever its size."""

import datetime as dt
from typing import Any

import pytest

from api.views import timeline
from episodes import ArgumentSpec, EpisodeMemory
from kg import Store

START = dt.datetime(2026, 3, 1, 8, 0, tzinfo=dt.UTC)


@pytest.fixture
def memory_with_twelve_episodes() -> EpisodeMemory:
    """Twelve ended episodes an hour apart, given out of order; every third annotated, with an
    augmentation run rated by Ana."""
    clock = {"now": START}
    memory = EpisodeMemory(Store(), clock=lambda: clock["now"])
    for k in (5, 0, 11, 3, 8, 1, 10, 2, 7, 4, 9, 6):
        begin = START + dt.timedelta(hours=k)
        clock["now"] = begin
        episode = memory.begin(
            ("babbling", "point")[k % 2],
            arguments=[ArgumentSpec("agent", f"person{k % 3}")],
            episode_id=f"e{k:02d}",
        )
        memory.end(episode.id, end=begin + dt.timedelta(minutes=30))
        if k % 3 == 0:
            memory.annotate(episode.id, key="phase", value=f"step {k}", start=begin, end=begin)
            run = memory.runs.start(episode.id, name="grasp-detector", producer="tests")
            memory.runs.end(episode.id, run.id)
            memory.ratings.rate(episode.id, run.id, person="Ana", value=k % 9 + 1)
    return memory


def test_pages_are_oldest_first_and_hold_what_the_memory_holds(
    memory_with_twelve_episodes: EpisodeMemory,
) -> None:
    memory = memory_with_twelve_episodes
    page = timeline.episode_list(memory, offset=4, limit=5)
    assert page.total == 12
    assert [e.id for e in page.episodes] == ["e04", "e05", "e06", "e07", "e08"]
    for entry in page.episodes:
        episode = memory.get(entry.id)
        assert (entry.activity, entry.begin, entry.end) == (
            episode.activity,
            episode.begin,
            episode.end,
        )
        assert entry.participants == [f"{a.role}: {a.value}" for a in episode.arguments]
        assert [(a.key, a.value) for a in entry.annotations] == [
            (a.key, a.value) for a in episode.annotations
        ]
        assert [r.name for r in entry.runs] == [r.name for r in memory.runs.of_episode(entry.id)]
    six = next(e for e in page.episodes if e.id == "e06")
    assert six.annotations[0].value == "step 6" and six.runs[0].name == "grasp-detector"
    assert [(r.person, r.value) for r in six.ratings] == [("Ana", 7)]
    assert next(e for e in page.episodes if e.id == "e05").ratings == []


def test_the_newest_page_is_the_last_episodes_oldest_first(
    memory_with_twelve_episodes: EpisodeMemory,
) -> None:
    page = timeline.episode_list(memory_with_twelve_episodes, offset=0, limit=3, newest=True)
    assert (page.total, page.offset) == (12, 9)
    assert [e.id for e in page.episodes] == ["e09", "e10", "e11"]
    everything = timeline.episode_list(memory_with_twelve_episodes, offset=5, limit=20, newest=True)
    assert everything.offset == 0 and len(everything.episodes) == 12


def test_a_page_costs_the_same_queries_whatever_its_size(
    memory_with_twelve_episodes: EpisodeMemory, monkeypatch: pytest.MonkeyPatch
) -> None:
    store = memory_with_twelve_episodes.store
    queries: list[str] = []
    for method in ("select", "select_each"):
        original = getattr(store, method)

        def counted(name: str, *args: Any, _original: Any = original, **kwargs: Any) -> Any:
            queries.append(name)
            return _original(name, *args, **kwargs)

        monkeypatch.setattr(store, method, counted)
    timeline.episode_list(memory_with_twelve_episodes, offset=0, limit=2)
    for_two = len(queries)
    queries.clear()
    timeline.episode_list(memory_with_twelve_episodes, offset=0, limit=12)
    assert len(queries) == for_two
