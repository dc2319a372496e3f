"""Domain errors mapped to HTTP answers, in one place.

Every error Engram raises on purpose has a 4xx (or 503) answer here, with ``detail`` and the
error's name; errors that know which input was wrong add ``field``, ``value`` and ``expected``.
"""

import json
from typing import Any

from fastapi import FastAPI, Request
from fastapi.responses import JSONResponse

from api.ask.errors import SpeechUnavailableError
from api.negotiation import NotAcceptable
from episodes import to_jsonable
from episodes.errors import EpisodeStateError
from episodes.streams.errors import CorruptRecordingError, StreamError
from kg.errors import (
    ConflictError,
    EngramError,
    InvalidInputError,
    NotFoundError,
    QueryRefusedError,
    QuerySyntaxError,
    QueryTooDeepError,
    QueryTooLongError,
    ReadOnlyStoreError,
    ResultTooLargeError,
    UnavailableError,
    UnsupportedQueryError,
)
from reasoners.errors import MemoryLoadingError, UnknownItemError

__all__ = ["install_error_handlers"]

# Most specific first: the first matching class decides the status. The four kinds of
# kg.errors close the list, so any error of the tree has an answer, and EngramError itself last.
_STATUS: list[tuple[type[Exception], int]] = [
    (QuerySyntaxError, 400),
    (QueryTooDeepError, 400),
    (UnsupportedQueryError, 400),
    (QueryRefusedError, 403),
    (QueryTooLongError, 413),
    (ResultTooLargeError, 400),
    (ReadOnlyStoreError, 409),
    (NotAcceptable, 406),
    (EpisodeStateError, 409),
    (CorruptRecordingError, 409),
    (InvalidInputError, 422),
    (NotFoundError, 404),
    (ConflictError, 409),
    (UnavailableError, 503),
    (StreamError, 400),
    (UnknownItemError, 404),
    (SpeechUnavailableError, 503),
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
    return JSONResponse(_without_server_paths(request, body), status_code=code)


def _without_server_paths(request: Request, body: dict[str, Any]) -> dict[str, Any]:
    """``body`` with the data directory's absolute path written ``<data>``: a client learns
    which file inside it, never where the server keeps it."""
    settings = getattr(request.app.state, "settings", None)
    if settings is None:
        return body
    roots = sorted({str(settings.data_dir.resolve()), str(settings.data_dir)}, key=len)[::-1]
    roots = [root for root in roots if len(root) > 1]  # never "/" or "."
    clean: dict[str, Any] = {}
    for key, value in body.items():
        if isinstance(value, str):
            for root in roots:
                value = value.replace(root, "<data>")
        clean[key] = value
    return clean


def install_error_handlers(app: FastAPI) -> None:
    for kind, _ in _STATUS:
        app.add_exception_handler(kind, _answer)
