"""The clock Engram reads "now" from: a function returning the current, time-zone-aware time.

Every part that depends on time (the scene memory's forgetting, the episodes, the writer's lease,
the server) takes a :data:`Clock`, so that a test, a demo or a dialogue can fix "now";
:func:`utc_now` is the real one, :class:`SimulatedClock` one moved by hand.

>>> utc_now().tzinfo is not None
True
"""

import datetime as dt
from collections.abc import Callable

__all__ = ["Clock", "SimulatedClock", "utc_now"]

Clock = Callable[[], dt.datetime]
"""Returns the current time as a time-zone-aware datetime."""


def utc_now() -> dt.datetime:
    """The current time, in UTC."""
    return dt.datetime.now(dt.UTC)


class SimulatedClock:
    """A :data:`Clock` moved by hand: it reads ``now``, which the caller sets or advances (a
    demo, a sample memory, a test). Nothing checks the times it is given.

    >>> clock = SimulatedClock(dt.datetime(2026, 1, 26, 8, tzinfo=dt.UTC))
    >>> clock.advance(hours=12).isoformat()
    '2026-01-26T20:00:00+00:00'
    """

    def __init__(self, start: dt.datetime) -> None:
        self.now = start

    def __call__(self) -> dt.datetime:
        return self.now

    def advance(self, **delta: float) -> dt.datetime:
        """Move ``now`` on by ``datetime.timedelta(**delta)``; the new time."""
        self.now += dt.timedelta(**delta)
        return self.now
