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

__all__ = ["install_error_handlers"]

# By kind: every error Engram raises on purpose is an EngramError of one of kg.errors' four kinds
# (invalid input, not found, conflict, unavailable). The SPARQL protocol's own answers for a
# query (400, 403, 413) and HTTP content negotiation (406) come first; the first matching class
# decides the status.
_STATUS: list[tuple[type[Exception], int]] = [
    (QuerySyntaxError, 400),
    (QueryTooDeepError, 400),
    (UnsupportedQueryError, 400),
    (QueryRefusedError, 403),
    (QueryTooLongError, 413),
    (ResultTooLargeError, 400),
    (ReadOnlyStoreError, 409),
    (NotAcceptable, 406),
    (InvalidInputError, 422),
    (NotFoundError, 404),
    (ConflictError, 409),
    (UnavailableError, 503),
    (EngramError, 400),  # an error of no kind: a bug to fix, answered as a bad request
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
