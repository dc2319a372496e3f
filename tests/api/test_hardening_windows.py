"""A window of any length costs the same to plan: "what happened between the years 1 and 9999"
(the web timeline's own question) lists no day buckets, where it once listed 3.6 million."""

import datetime as dt

import pytest

from episodes import time_index


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
    assert len(time_index.window_days(*week) or []) == 8  # seven days and "running"
    assert listed == [7]
