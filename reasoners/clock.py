"""A clock a test, a demo or an analyst can set, to replay a life over simulated days.

Forgetting depends on time (the grace period, the episodic decay). A :class:`SettableClock`
follows the real clock until it is set or advanced; from then on it stands still at the time it
was given, and moves only when advanced. It never goes back: the memory's times (created, last
accessed, forgotten) must stay in order.

>>> import datetime as dt
>>> clock = SettableClock()
>>> clock.set(dt.datetime(2100, 1, 1, 9, tzinfo=dt.UTC))
>>> clock.advance(3600 * 24)
>>> clock().isoformat()
'2100-01-02T09:00:00+00:00'
"""

import datetime as dt
import threading

from kg.clock import Clock, utc_now

__all__ = ["SettableClock", "read_clock"]


class SettableClock:
    """A clock that reads ``real()`` until :meth:`set` or :meth:`advance` fixes it."""

    def __init__(self, real: Clock = utc_now) -> None:
        self._real = real
        self._fixed: dt.datetime | None = None
        self._lock = threading.Lock()

    def __call__(self) -> dt.datetime:
        with self._lock:
            return self._fixed if self._fixed is not None else self._real()

    def set(self, when: dt.datetime) -> None:
        """Stand still at ``when``. Raises ``ValueError`` for a naive time or one before now."""
        if not isinstance(when, dt.datetime) or when.tzinfo is None:
            raise ValueError(f"time: got {when!r}, expected a timezone-aware datetime")
        with self._lock:
            now = self._fixed if self._fixed is not None else self._real()
            if when < now:
                raise ValueError(
                    f"time: got {when.isoformat()}, expected {now.isoformat()} or later "
                    "(the memory's clock never goes back)"
                )
            self._fixed = when

    def advance(self, seconds: float) -> None:
        """Move on by ``seconds`` (and stand still there). Raises ``ValueError`` unless
        ``seconds`` is a finite number of at least 0."""
        if not isinstance(seconds, int | float) or not 0 <= seconds < 1e11:
            raise ValueError(f"seconds: got {seconds!r}, expected a number from 0 to 1e11")
        with self._lock:
            now = self._fixed if self._fixed is not None else self._real()
            self._fixed = now + dt.timedelta(seconds=seconds)

    def snapshot(self) -> dt.datetime | None:
        """The state :meth:`restore` puts back (a list that fails leaves the clock as it was)."""
        with self._lock:
            return self._fixed

    def restore(self, state: dt.datetime | None) -> None:
        with self._lock:
            self._fixed = state


def read_clock(clock: Clock) -> dt.datetime:
    """The time ``clock`` gives, to the millisecond (the precision of the memory's times, in
    the model as in the store). Raises ``ValueError`` if it is not a timezone-aware datetime."""
    now = clock()
    if not isinstance(now, dt.datetime) or now.tzinfo is None:
        raise ValueError(f"clock: got {now!r}, expected a timezone-aware datetime")
    # xsd:dateTime with microseconds makes HermiT refuse an export
    return now.replace(microsecond=now.microsecond - now.microsecond % 1000)
