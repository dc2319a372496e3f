"""Times in words, as a dialogue says them."""

import datetime as dt

import pytest

from episodes.times import say_when

NOW = dt.datetime(2026, 2, 26, 10, 0, tzinfo=dt.UTC)


@pytest.mark.parametrize(
    ("moment", "expected"),
    [
        (NOW - dt.timedelta(seconds=20), "just now"),
        (NOW - dt.timedelta(minutes=1), "one minute ago, today at 09:59"),
        (NOW - dt.timedelta(hours=3), "three hours ago, today at 07:00"),
        (dt.datetime(2026, 2, 25, 23, 0, tzinfo=dt.UTC), "yesterday at 23:00"),
        (dt.datetime(2026, 2, 21, 9, 0, tzinfo=dt.UTC), "five days ago, on February 21st"),
        (dt.datetime(2026, 2, 2, 9, 0, tzinfo=dt.UTC), "three weeks ago, on February 2nd"),
        (dt.datetime(2026, 1, 26, 15, 30, tzinfo=dt.UTC), "one month ago, on January 26th"),
        (dt.datetime(2025, 11, 23, 9, 0, tzinfo=dt.UTC), "three months ago, on November 23rd"),
        (dt.datetime(2024, 2, 11, 9, 0, tzinfo=dt.UTC), "two years ago, on February 11th, 2024"),
        (NOW + dt.timedelta(days=3), "in three days, on March 1st"),
    ],
)
def test_say_when(moment: dt.datetime, expected: str) -> None:
    assert say_when(moment, NOW) == expected


def test_phrase_uses_the_time_zone_of_now() -> None:
    paris = dt.timezone(dt.timedelta(hours=1))
    late = dt.datetime(2026, 2, 25, 23, 30, tzinfo=dt.UTC)  # 00:30 on the 26th in Paris
    assert say_when(late, NOW.astimezone(paris)) == "ten hours ago, today at 00:30"
