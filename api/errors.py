"""Domain errors mapped to HTTP answers, in one place.

Every error Engram raises on purpose has a 4xx (or 503) answer here, with ``detail`` and the
error's name; errors that know which input was wrong add ``field``, ``value`` and ``expected``.
"""

import json
from typing import Any

from fastapi import FastAPI, Request
from fastapi.responses import JSONResponse

from api.negotiation import NotAcceptable
from episodes import to_jsonable
from episodes.errors import EpisodeStateError, InvalidInputError, NotFoundError
from episodes.streams.errors import (
    CorruptRecordingError,
    InvalidSampleError,
    RecordingNotFoundError,
    RecordingStateError,
    StreamError,
    UnknownProviderError,
)
from kg.errors import (
    EngramError,
    QueryRefusedError,
    QuerySyntaxError,
    QueryTimeoutError,
    ResultTooLargeError,
    StoreError,
)
from reasoners.errors import MemoryLoadingError

__all__ = ["install_error_handlers"]

# Most specific first: the first matching class decides the status.
_STATUS: list[tuple[type[Exception], int]] = [
    (QuerySyntaxError, 400),
    (QueryRefusedError, 403),
    (NotAcceptable, 406),
    (QueryTimeoutError, 503),
    (ResultTooLargeError, 400),
    (StoreError, 503),
    (InvalidInputError, 422),
    (NotFoundError, 404),
    (EpisodeStateError, 409),
    (InvalidSampleError, 422),
    (UnknownProviderError, 404),
    (RecordingNotFoundError, 404),
    (RecordingStateError, 409),
    (CorruptRecordingError, 409),
    (StreamError, 400),
    (MemoryLoadingError, 503),
    (EngramError, 400),
]


def _answer(request: Request, error: Exception) -> JSONResponse:
    code = next(code for kind, code in _STATUS if isinstance(error, kind))
    body: dict[str, Any] = {"detail": str(error), "error": type(error).__name__}
    for name in ("field", "value", "expected"):
        if hasattr(error, name):
            value = to_jsonable(getattr(error, name))
            try:
                json.dumps(value)
            except (TypeError, ValueError):
                value = repr(value)
            body[name] = value
    return JSONResponse(body, status_code=code)


def install_error_handlers(app: FastAPI) -> None:
    for kind, _ in _STATUS:
        app.add_exception_handler(kind, _answer)
