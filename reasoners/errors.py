"""The exceptions of the scene memory.

EngramError (kg), each error also of one of kg.errors' kinds
└── MemoryReasonerError
    ├── InvalidSceneError       the primitives cannot form a scene, or a bad cue (ValueError)
    ├── MemoryLoadingError      the memory is still being opened, or opening it failed (503)
    ├── OperationFailedError    an operation of a commit failed; nothing of the commit was written
    ├── PolicyError             the memory policy in the store lacks a value or holds a bad one
    ├── UnknownItemError        no live class or experienced scene has this IRI (KeyError)
    │   └── NotInTrashError     restore was asked for an IRI that is not in the trash
    └── RestoreConflictError    a live class already has the signature of the class to restore
"""

from kg.errors import ConflictError, EngramError, InvalidInputError, NotFoundError, UnavailableError

__all__ = [
    "InvalidSceneError",
    "MemoryLoadingError",
    "MemoryReasonerError",
    "NotInTrashError",
    "OperationFailedError",
    "PolicyError",
    "RestoreConflictError",
    "UnknownItemError",
]


class MemoryReasonerError(EngramError):
    """Base of the scene memory's errors."""


class InvalidSceneError(MemoryReasonerError, InvalidInputError):
    """The primitives cannot form a scene (duplicate ids, no relation), or a cue is malformed."""


class MemoryLoadingError(MemoryReasonerError, UnavailableError):
    """The scene memory is still being opened in the background (or opening it failed)."""


class OperationFailedError(MemoryReasonerError):
    """An operation of :meth:`~reasoners.memory.SceneMemory.commit` failed, so nothing of the
    commit was written: ``index`` is its position in the list, ``error`` what it raised."""

    def __init__(self, index: int, error: Exception) -> None:
        super().__init__(f"operations[{index}]: {error}")
        self.index = index
        self.error = error


class PolicyError(MemoryReasonerError, ConflictError):
    """The memory policy in the store lacks a value or holds one of the wrong kind."""


class UnknownItemError(MemoryReasonerError, NotFoundError, KeyError):
    """No live learned class or experienced scene has this IRI."""

    def __str__(self) -> str:  # KeyError would quote the message
        return str(self.args[0]) if self.args else ""


class NotInTrashError(UnknownItemError):
    """Restore was asked for an IRI that the trash does not hold."""


class RestoreConflictError(MemoryReasonerError, ConflictError):
    """A live class already has the signature of the class to restore."""
