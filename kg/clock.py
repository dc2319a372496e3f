"""The clock Engram reads "now" from: a function returning the current, time-zone-aware time.

Every part that depends on time (the scene memory's forgetting, the episodes, the writer's lease,
the server) takes a :data:`Clock`, so that a test, a demo or a dialogue can fix "now";
:func:`utc_now` is the real one.

>>> utc_now().tzinfo is not None
True
"""

import datetime as dt
from collections.abc import Callable

__all__ = ["Clock", "utc_now"]

Clock = Callable[[], dt.datetime]
"""Returns the current time as a time-zone-aware datetime."""


def utc_now() -> dt.datetime:
    """The current time, in UTC."""
    return dt.datetime.now(dt.UTC)
