"""Time windows and episodes of any length cost the same to index: "what happened between the
years 1 and 9999" (the web timeline's own question) lists no day buckets, and an episode of
those years writes one mark, where each once meant 3.6 million days."""

import datetime as dt
from pathlib import Path

import pytest

from episodes import EpisodeMemory, time_index
from kg import Store, ensure_ontology


def test_a_long_window_lists_no_days(monkeypatch: pytest.MonkeyPatch) -> None:
    listed: list[int] = []
    days = time_index._days

    def counted(start: dt.datetime, end: dt.datetime) -> list[object]:
        found = days(start, end)
        listed.append(len(found))
        return list(found)

    monkeypatch.setattr(time_index, "_days", counted)
    ever = (dt.datetime(1, 1, 1, tzinfo=dt.UTC), dt.datetime(9999, 12, 31, tzinfo=dt.UTC))
    assert time_index.window_days(*ever) is None
    week = (dt.datetime(2026, 3, 1, tzinfo=dt.UTC), dt.datetime(2026, 3, 7, tzinfo=dt.UTC))
    assert len(time_index.window_days(*week) or []) == 9  # seven days, "running", "long"
    assert listed == [7]


def test_an_episode_of_millennia_writes_one_day_mark_and_is_found(tmp_path: Path) -> None:
    store = Store(tmp_path / "store")
    ensure_ontology(store)
    memory = EpisodeMemory(store, data_dir=tmp_path)
    try:
        memory.begin("watch", episode_id="ages", begin="0001-01-01T00:00:00+00:00")
        memory.end("ages", end="9999-12-31T00:00:00+00:00")
        memory.begin("wave", episode_id="short", begin="2026-03-02T10:00:00+00:00")
        memory.end("short", end="2026-03-02T10:05:00+00:00")
        days = list(store.quads(None, time_index.CUE_DAY, None, None))
        assert len(days) == 2  # "long" for the first, one day for the second
        inside = memory.between("2026-03-02T00:00:00+00:00", "2026-03-03T00:00:00+00:00")
        assert sorted(r.episode.id for r in inside) == ["ages", "short"]
        before = memory.between("0500-01-01T00:00:00+00:00", "0500-01-02T00:00:00+00:00")
        assert [r.episode.id for r in before] == ["ages"]
    finally:
        memory.close()
