"""The errors of the stream recorder, in one tree.

::

    StreamError (kg.errors.EngramError; each error also of one of its kinds)
    ├── InvalidSampleError (ValueError)      a sample or provider setting is malformed
    ├── UnknownProviderError (LookupError)   no provider of that name in the recording
    ├── RecordingStateError                  the recording is closed, or already open
    ├── RecordingNotFoundError (LookupError) no recording for that episode or path
    └── CorruptRecordingError                the file cannot be read at all
"""

from kg.errors import ConflictError, EngramError, InvalidInputError, NotFoundError

__all__ = [
    "CorruptRecordingError",
    "InvalidSampleError",
    "RecordingNotFoundError",
    "RecordingStateError",
    "StreamError",
    "UnknownProviderError",
]


class StreamError(EngramError):
    """Base class of every error raised by ``episodes.streams``."""


class InvalidSampleError(StreamError, InvalidInputError):
    """A sample, a tick or a provider setting does not have the expected form.

    >>> str(InvalidSampleError("rate_limit_hz", -1, "a positive number"))
    'rate_limit_hz: got -1, expected a positive number'
    """

    def __init__(self, field: str, value: object, expected: str) -> None:
        shown = repr(value)
        if len(shown) > 120:
            shown = shown[:117] + "..."
        super().__init__(f"{field}: got {shown}, expected {expected}")
        self.field, self.value, self.expected = field, value, expected


class UnknownProviderError(StreamError, NotFoundError):
    """A sample names a provider the recording does not have."""

    def __str__(self) -> str:
        return str(self.args[0]) if self.args else "unknown provider"


class RecordingStateError(StreamError, ConflictError):
    """The operation needs an open recording and it is closed, or the reverse."""


class RecordingNotFoundError(StreamError, NotFoundError):
    """No recording exists for the episode or at the path given."""

    def __str__(self) -> str:
        return str(self.args[0]) if self.args else "recording not found"


class CorruptRecordingError(StreamError, ConflictError):
    """The recording's file is not an MCAP file written by the recorder."""
