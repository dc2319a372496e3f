"""The words the question grammar knows: objects, relations, times, numbers, and the names the
memories hold (activities and participants of episodes).

>>> OBJECTS["ball"], RELATIONS["in front of"]
('Sphere', 'isInFrontOf')
>>> number_from_words("twenty one"), number_from_words("7"), say_number(42)
(21, 7, 'forty two')
"""

import datetime as dt
import threading
import time
from dataclasses import dataclass

from pyoxigraph import Literal

from kg import Store

__all__ = [
    "NUMBER_WORDS",
    "OBJECTS",
    "RELATIONS",
    "TIMES",
    "NameCache",
    "Names",
    "number_from_words",
    "say_number",
    "time_window",
]

OBJECTS = {
    "ball": "Sphere",
    "sphere": "Sphere",
    "orange": "Sphere",
    "apple": "Sphere",
    "cone": "Cone",
    "cylinder": "Cylinder",
    "cup": "Cylinder",
    "can": "Cylinder",
    "bottle": "Cylinder",
    "mug": "Cylinder",
    "table": "Plane",
    "plane": "Plane",
    "floor": "Plane",
    "wall": "Plane",
    "tray": "Plane",
}
"""Object words and the primitive kind each is perceived as."""

RELATIONS = {
    "on top of": "isAboveOf",
    "on": "isAboveOf",
    "above": "isAboveOf",
    "over": "isAboveOf",
    "under": "isBelowOf",
    "below": "isBelowOf",
    "beneath": "isBelowOf",
    "behind": "isBehindOf",
    "in front of": "isInFrontOf",
    "left of": "isLeftOf",
    "to the left of": "isLeftOf",
    "right of": "isRightOf",
    "to the right of": "isRightOf",
    "parallel to": "isParallelWith",
    "perpendicular to": "isPerpendicularWith",
}
"""Relation phrases and the spatial relation each names (frame: x right, y behind, z up)."""

TIMES = (
    "today",
    "yesterday",
    "this morning",
    "this afternoon",
    "this evening",
    "yesterday morning",
    "yesterday afternoon",
    "yesterday evening",
    "last night",
    "this week",
    "last week",
)
"""Time phrases, each a window of the clock's local calendar (see :func:`time_window`)."""

_UNITS = [
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
    "thirteen",
    "fourteen",
    "fifteen",
    "sixteen",
    "seventeen",
    "eighteen",
    "nineteen",
]
_TENS = ["twenty", "thirty", "forty", "fifty", "sixty", "seventy", "eighty", "ninety"]
NUMBER_WORDS = tuple(_UNITS[1:] + _TENS)
_PARTS = {"morning": (6, 12), "afternoon": (12, 18), "evening": (18, 24), "night": (0, 6)}


def say_number(n: int) -> str:
    """``n`` (1 to 99) in words; larger numbers as digits."""
    if n < 20:
        return _UNITS[n]
    if n < 100:
        tens, unit = divmod(n, 10)
        return _TENS[tens - 2] + (f" {_UNITS[unit]}" if unit else "")
    return str(n)


def number_from_words(text: str) -> int | None:
    """The number written as digits or as words up to ninety nine, else None."""
    text = text.strip().replace("-", " ")
    if text.isdigit():
        return int(text)
    words = text.split()
    if len(words) == 1 and words[0] in _UNITS:
        return _UNITS.index(words[0])
    if words and words[0] in _TENS and len(words) <= 2:
        value = 20 + 10 * _TENS.index(words[0])
        if len(words) == 2:
            if words[1] not in _UNITS[1:10]:
                return None
            value += _UNITS.index(words[1])
        return value
    return None


def time_window(phrase: str, now: dt.datetime) -> tuple[dt.datetime, dt.datetime]:
    """The window a time phrase names, in ``now``'s time zone; the current day or week ends now.

    Raises ``KeyError`` for a phrase not in :data:`TIMES`.
    """
    if phrase not in TIMES:
        raise KeyError(phrase)
    midnight = now.replace(hour=0, minute=0, second=0, microsecond=0)
    if phrase.endswith("week"):
        monday = midnight - dt.timedelta(days=now.weekday())
        if phrase == "this week":
            return monday, now
        return monday - dt.timedelta(days=7), monday
    if phrase == "last night":
        start = midnight - dt.timedelta(hours=6)
        return start, midnight + dt.timedelta(hours=6)
    day = midnight - dt.timedelta(days=1) if phrase.startswith("yesterday") else midnight
    part = phrase.split()[-1]
    if part in _PARTS:
        first, last = _PARTS[part]
        start, end = day + dt.timedelta(hours=first), day + dt.timedelta(hours=last)
    else:
        start, end = day, day + dt.timedelta(days=1)
    return start, (min(end, now) if day == midnight else end)


@dataclass(frozen=True)
class Names:
    """The activity names and participant labels the episodes hold."""

    activities: tuple[str, ...]
    participants: tuple[str, ...]

    def find(self, text: str, kind: str) -> str | None:
        """The stored name equal to ``text`` ignoring case and spacing, or None."""
        wanted = " ".join(text.lower().split())
        pool = self.activities if kind == "activity" else self.participants
        return next((name for name in pool if " ".join(name.lower().split()) == wanted), None)


class NameCache:
    """The names of ``store``'s episodes, read once and read again only when needed.

    Reading them scans every episode (about 0.3 s at 10,000), so a question does not pay for it:
    names are only ever added, and :meth:`find` reads them again when a name is missing (at
    most once per ``retry_s``), :meth:`get` when the store changed and they are older than
    ``max_age_s`` (the speech grammar uses that).
    """

    def __init__(self, store: Store, *, max_age_s: float = 5.0, retry_s: float = 1.0) -> None:
        self.store = store
        self.max_age_s = max_age_s
        self.retry_s = retry_s
        self._lock = threading.Lock()
        self._names: Names | None = None
        self._generation = -1
        self._read_at = 0.0

    def _read(self) -> Names:
        self._generation = self.store.generation
        self._read_at = time.monotonic()
        activities: list[str] = []
        participants: list[str] = []
        for row in self.store.select("ask_episode_names"):
            name, kind = row["name"], row["kind"]
            if isinstance(name, Literal) and isinstance(kind, Literal):
                (activities if kind.value == "activity" else participants).append(name.value)
        self._names = Names(tuple(activities), tuple(participants))
        return self._names

    def get(self) -> Names:
        """The names, read again if the store changed more than ``max_age_s`` seconds ago."""
        with self._lock:
            stale = self._generation != self.store.generation
            if self._names is None or (
                stale and time.monotonic() - self._read_at >= self.max_age_s
            ):
                return self._read()
            return self._names

    def find(self, text: str, kind: str) -> str | None:
        """The stored name equal to ``text`` ignoring case and spacing; None if there is none
        (after reading the names again, if the store changed since they were read)."""
        with self._lock:
            names = self._names or self._read()
            found = names.find(text, kind)
            if (
                found is None
                and self._generation != self.store.generation
                and time.monotonic() - self._read_at >= self.retry_s
            ):
                found = self._read().find(text, kind)
            return found

    def refresh(self) -> Names:
        """Read the names now."""
        with self._lock:
            return self._read()
