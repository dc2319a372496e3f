"""Domain errors mapped to HTTP answers, in one place."""

from fastapi import FastAPI, Request
from fastapi.responses import JSONResponse

from api.negotiation import NotAcceptable
from kg.errors import (
    EngramError,
    QueryRefusedError,
    QuerySyntaxError,
    QueryTimeoutError,
    ResultTooLargeError,
    StoreError,
)

__all__ = ["install_error_handlers"]

_STATUS: list[tuple[type[Exception], int]] = [
    (QuerySyntaxError, 400),
    (QueryRefusedError, 403),
    (NotAcceptable, 406),
    (QueryTimeoutError, 503),
    (ResultTooLargeError, 400),
    (StoreError, 503),
    (EngramError, 400),
]


def _answer(request: Request, error: Exception) -> JSONResponse:
    code = next(code for kind, code in _STATUS if isinstance(error, kind))
    return JSONResponse({"detail": str(error), "error": type(error).__name__}, status_code=code)


def install_error_handlers(app: FastAPI) -> None:
    for kind, _ in _STATUS:
        app.add_exception_handler(kind, _answer)
