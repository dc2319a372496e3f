"""The exceptions of the autobiographical memory.

EngramError (kg), each error also of one of kg.errors' kinds
└── EpisodeError
    ├── InvalidInputError       bad value (HTTP 422): names field, value, expected (kg's
    │                           InvalidValueError)
    ├── NotFoundError           no such episode, run or cue match (HTTP 404)
    │   └── EpisodeNotFoundError
    └── EpisodeStateError       does not fit the state, e.g. ending twice (HTTP 409)
"""

from kg import errors as kinds
from kg.errors import EngramError

__all__ = [
    "EpisodeError",
    "EpisodeNotFoundError",
    "EpisodeStateError",
    "InvalidInputError",
    "NotFoundError",
]


class EpisodeError(EngramError):
    """Base of the errors of the autobiographical memory."""


class InvalidInputError(EpisodeError, kinds.InvalidValueError):
    """A value is malformed or out of range; nothing was written."""


class NotFoundError(EpisodeError, kinds.NotFoundError):
    """Nothing in the memory matches what was asked for."""


class EpisodeNotFoundError(NotFoundError):
    """No episode has this id."""

    def __init__(self, episode_id: str) -> None:
        self.episode_id = episode_id
        super().__init__(f"episode: no episode with id {episode_id!r}")


class EpisodeStateError(EpisodeError, kinds.ConflictError):
    """The operation does not fit the episode's state (e.g. it has already ended)."""
