"""The open recordings of one process, by episode id.

>>> import tempfile, pathlib
>>> registry = RecordingRegistry()
>>> with tempfile.TemporaryDirectory() as tmp:
...     rec = registry.open("ep-1", pathlib.Path(tmp) / "ep-1")
...     registry.get("ep-1") is rec, "ep-1" in registry
...     registry.close("ep-1")
...     "ep-1" in registry
(True, True)
[]
False
"""

from __future__ import annotations

import re
import threading
from pathlib import Path
from typing import Any

from episodes.streams.errors import (
    InvalidSampleError,
    RecordingNotFoundError,
    RecordingStateError,
)
from episodes.streams.ledger import ChannelStats
from episodes.streams.recorder import Recorder

__all__ = ["RecordingRegistry", "bag_path", "check_episode_id"]

_EPISODE_ID = re.compile(r"[A-Za-z0-9][A-Za-z0-9._-]{0,127}")


def check_episode_id(episode_id: str) -> str:
    """Return the id if it is safe as a directory name, else raise.

    Raises:
        InvalidSampleError: empty, too long, or with characters other than letters, digits,
            ``.``, ``_`` and ``-`` (it must not start with ``.``, ``_`` or ``-``).
    """
    if not isinstance(episode_id, str) or not _EPISODE_ID.fullmatch(episode_id):
        raise InvalidSampleError(
            "episode_id", episode_id, "1-128 letters, digits, '.', '_' or '-', not first"
        )
    return episode_id


def bag_path(root: Path, episode_id: str) -> Path:
    """Where an episode's streams live under ``root``: ``root/<episode id>`` (a bag directory).

    >>> bag_path(Path("/data/streams"), "ep-1").as_posix()
    '/data/streams/ep-1'
    """
    return root / check_episode_id(episode_id)


class RecordingRegistry:
    """A thread-safe map episode id -> open :class:`Recorder`."""

    def __init__(self) -> None:
        self._lock = threading.Lock()
        self._open: dict[str, Recorder] = {}

    def open(self, episode_id: str, path: Path | str, **options: Any) -> Recorder:
        """Start recording an episode into ``path`` (a new bag directory).

        ``options`` go to :class:`Recorder` (``max_queue_bytes``, ``flush_interval_s``, ...).

        Raises:
            RecordingStateError: the episode is recording already, or ``path`` exists.
            InvalidSampleError: a bad episode id or option.
        """
        check_episode_id(episode_id)
        with self._lock:
            if episode_id in self._open:
                raise RecordingStateError(f"episode_id: {episode_id!r} is recording already")
            recorder = Recorder(path, episode_id=episode_id, **options)
            self._open[episode_id] = recorder
            return recorder

    def get(self, episode_id: str) -> Recorder:
        """The open recorder of an episode.

        Raises:
            RecordingNotFoundError: the episode is not recording.
        """
        with self._lock:
            recorder = self._open.get(episode_id)
        if recorder is None:
            raise RecordingNotFoundError(f"episode_id: {episode_id!r} is not recording")
        return recorder

    def close(self, episode_id: str) -> list[ChannelStats]:
        """Finish an episode's recording and return its channel counts.

        Raises:
            RecordingNotFoundError: the episode is not recording.
        """
        with self._lock:
            recorder = self._open.pop(episode_id, None)
        if recorder is None:
            raise RecordingNotFoundError(f"episode_id: {episode_id!r} is not recording")
        return recorder.close()

    def close_all(self) -> dict[str, list[ChannelStats]]:
        """Close every open recording (at shutdown)."""
        with self._lock:
            recorders, self._open = self._open, {}
        return {episode: rec.close() for episode, rec in recorders.items()}

    def __contains__(self, episode_id: object) -> bool:
        with self._lock:
            return episode_id in self._open

    def episodes(self) -> list[str]:
        """The ids of the episodes recording now."""
        with self._lock:
            return sorted(self._open)
