"""Time-zone-aware times: parsing and validation, RDF literals, and phrases a dialogue can say.

>>> import datetime as dt
>>> now = dt.datetime(2026, 2, 26, 10, 0, tzinfo=dt.UTC)
>>> say_when(dt.datetime(2026, 1, 26, 15, 30, tzinfo=dt.UTC), now)
'one month ago, on January 26th'
>>> say_when(now - dt.timedelta(minutes=5), now)
'five minutes ago, today at 09:55'
>>> parse_time("2026-01-26T15:30:00", "begin")  # doctest: +ELLIPSIS
Traceback (most recent call last):
...
episodes.errors.InvalidInputError: begin: got '2026-01-26T15:30:00', expected an ISO 8601 ...
"""

import datetime as dt

from pyoxigraph import Literal

from episodes.errors import InvalidInputError
from kg.clock import Clock
from ontologies.vocab import XSD_DATETIME

__all__ = [
    "from_literal",
    "from_ns",
    "now",
    "parse_time",
    "say_when",
    "system_clock",
    "time_or_now",
    "to_literal",
]

EXPECTED = "an ISO 8601 date-time with a time zone, e.g. 2026-01-26T15:30:00+01:00"
_WORDS = [
    "zero",
    "one",
    "two",
    "three",
    "four",
    "five",
    "six",
    "seven",
    "eight",
    "nine",
    "ten",
    "eleven",
    "twelve",
]


def system_clock() -> dt.datetime:
    """The current time in the machine's local time zone."""
    return dt.datetime.now().astimezone()


def now(clock: Clock) -> dt.datetime:
    """What ``clock`` says; raises :class:`ValueError` if it returns a naive datetime."""
    moment = clock()
    if moment.tzinfo is None:
        raise ValueError("clock: returned a naive datetime; it must be time-zone aware")
    return moment


def time_or_now(clock: Clock, value: dt.datetime | str | None, field: str) -> dt.datetime:
    """``value`` parsed (see :func:`parse_time`), or what ``clock`` says when it is ``None``."""
    return now(clock) if value is None else parse_time(value, field)


def parse_time(value: str | dt.datetime, field: str) -> dt.datetime:
    """``value`` as an aware datetime; raises :class:`InvalidInputError` naming ``field``."""
    if isinstance(value, dt.datetime):
        parsed = value
    elif isinstance(value, str):
        try:
            parsed = dt.datetime.fromisoformat(value.strip())
        except ValueError:
            raise InvalidInputError(field, value, EXPECTED) from None
    else:
        raise InvalidInputError(field, value, EXPECTED)
    if parsed.tzinfo is None or parsed.utcoffset() is None:
        raise InvalidInputError(field, value if isinstance(value, str) else str(value), EXPECTED)
    return parsed


def to_literal(moment: dt.datetime) -> Literal:
    """An ``xsd:dateTime`` literal keeping the time zone offset."""
    if moment.tzinfo is None:
        raise ValueError(f"time: got naive {moment.isoformat()}, expected a time-zone-aware time")
    return Literal(moment.isoformat(), datatype=XSD_DATETIME)


def from_literal(literal: object) -> dt.datetime:
    """The aware datetime of an ``xsd:dateTime`` literal read from the store."""
    if not isinstance(literal, Literal) or literal.datatype != XSD_DATETIME:
        raise ValueError(f"expected an xsd:dateTime literal, got {literal!r}")
    return dt.datetime.fromisoformat(literal.value)


def from_ns(ns: int | None) -> dt.datetime | None:
    """The UTC time of a timestamp in nanoseconds since the epoch (a recording's or a bag's
    clock); None for None.

    >>> from_ns(1_767_225_600_500_000_000)
    datetime.datetime(2026, 1, 1, 0, 0, 0, 500000, tzinfo=datetime.timezone.utc)
    """
    return None if ns is None else dt.datetime.fromtimestamp(ns / 1e9, dt.UTC)


def _count(n: int, unit: str) -> str:
    word = _WORDS[n] if n < len(_WORDS) else str(n)
    return f"{word} {unit}{'' if n == 1 else 's'}"


def _ordinal(day: int) -> str:
    suffix = "th" if 11 <= day % 100 <= 13 else {1: "st", 2: "nd", 3: "rd"}.get(day % 10, "th")
    return f"{day}{suffix}"


def _months_between(earlier: dt.datetime, later: dt.datetime) -> int:
    months = (later.year - earlier.year) * 12 + later.month - earlier.month
    if later.day < earlier.day:  # calendar months, as people count them: Jan 26 -> Feb 26
        months -= 1
    return months


def say_when(moment: dt.datetime, now: dt.datetime) -> str:
    """How a person would say when ``moment`` was, seen from ``now`` (in ``now``'s time zone).

    "just now", "five minutes ago, today at 09:55", "yesterday at 14:05",
    "three days ago, on January 23rd", "one month ago, on January 26th",
    "two years ago, on January 26th, 2024"; times after ``now`` read "in ...".
    """
    moment = moment.astimezone(now.tzinfo)
    future = moment > now
    earlier, later = (now, moment) if future else (moment, now)
    seconds = (later - earlier).total_seconds()
    clock = moment.strftime("%H:%M")
    date = f"{moment.strftime('%B')} {_ordinal(moment.day)}"
    days = (later.date() - earlier.date()).days
    months = _months_between(earlier, later)

    def ago(amount: str) -> str:
        return f"in {amount}" if future else f"{amount} ago"

    if seconds < 60:
        return "just now"
    if days == 0:
        amount = (
            _count(int(seconds // 60), "minute")
            if seconds < 3600
            else _count(int(seconds // 3600), "hour")
        )
        return f"{ago(amount)}, today at {clock}"
    if days == 1:
        return f"{'tomorrow' if future else 'yesterday'} at {clock}"
    if days < 14:
        return f"{ago(_count(days, 'day'))}, on {date}"
    if months < 1:
        return f"{ago(_count(days // 7, 'week'))}, on {date}"
    if months < 12:
        return f"{ago(_count(months, 'month'))}, on {date}"
    return f"{ago(_count(months // 12, 'year'))}, on {date}, {moment.year}"
