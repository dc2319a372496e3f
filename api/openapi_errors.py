"""The error answers in the OpenAPI description, as the service really gives them.

FastAPI documents only 200 and its own 422 (a list of validation errors). The service also
answers with the body :class:`ErrorBody` that ``api/errors.py`` writes for a domain error: 404
for an unknown episode or recording, 409 for a state conflict, 422 for a value that parses but
is out of range (with ``field``, ``value``, ``expected``), 401 without the token. Routes can
name their codes with ``responses=error_responses(...)``; :func:`install_error_docs` adds the
ones every route of a kind can give, so a client generated from the description expects them.
"""

from collections.abc import Callable
from typing import Any

from fastapi import FastAPI
from pydantic import BaseModel

__all__ = ["ErrorBody", "error_responses", "install_error_docs"]


class ErrorBody(BaseModel):
    """What a domain error answers: the message, the error's name, and the input it blames."""

    detail: str
    error: str | None = None
    field: str | None = None
    value: Any = None
    expected: str | None = None


_DESCRIPTIONS = {
    400: "Bad request: the message says what is wrong",
    401: "The write token is missing or wrong",
    403: "Refused: the request would write or reach outside the store",
    404: "Not found: no such episode, recording, run or provider",
    406: "No acceptable media type for this answer",
    409: "Conflict with the current state (ended, not recording, unreadable recording)",
    413: "The request body or query is longer than the limit",
    415: "Unsupported request media type",
    422: "Invalid input: FastAPI's validation errors, or a domain error naming the field",
    503: "Unavailable now (time limit, a query worker that died, the store): retry later",
}
_ERROR_SCHEMA = {"$ref": "#/components/schemas/ErrorBody"}
_VALIDATION_SCHEMA = {"$ref": "#/components/schemas/HTTPValidationError"}


def error_responses(*codes: int) -> dict[int | str, dict[str, Any]]:
    """``responses=`` for a route answering ``codes`` with :class:`ErrorBody`."""
    return {code: {"model": ErrorBody, "description": _DESCRIPTIONS[code]} for code in codes}


def _codes_of(operation: dict[str, Any]) -> set[int]:
    """The error codes every operation of this shape can answer, read from its description."""
    parameters = operation.get("parameters", [])
    codes: set[int] = set()
    if parameters or "requestBody" in operation:
        codes.add(422)
    if any(p.get("in") == "header" and p.get("name") == "authorization" for p in parameters):
        codes.add(401)  # require_token's header
    if set(operation.get("tags", [])) & {"episodes", "streams"}:
        codes.add(422)
        if any(p.get("in") == "path" for p in parameters):
            codes |= {404, 409}
    return codes


def install_error_docs(app: FastAPI) -> None:
    """Document the error answers of every operation of ``app`` in its OpenAPI description."""
    original: Callable[[], dict[str, Any]] = app.openapi

    def openapi() -> dict[str, Any]:
        if app.openapi_schema is not None:
            return app.openapi_schema
        spec = original()
        schemas = spec.setdefault("components", {}).setdefault("schemas", {})
        schemas.setdefault("ErrorBody", ErrorBody.model_json_schema())
        for path in spec.get("paths", {}).values():
            for operation in path.values():
                responses = operation.setdefault("responses", {})
                for code in sorted(_codes_of(operation)):
                    _document(responses, code)
        app.openapi_schema = spec
        return spec

    app.openapi = openapi  # type: ignore[method-assign]


def _document(responses: dict[str, Any], code: int) -> None:
    if code == 422:
        if "HTTPValidationError" not in str(responses.get("422", "")):
            schema: dict[str, Any] = _ERROR_SCHEMA
        else:
            schema = {"anyOf": [_VALIDATION_SCHEMA, _ERROR_SCHEMA]}
        responses["422"] = {
            "description": _DESCRIPTIONS[422],
            "content": {"application/json": {"schema": schema}},
        }
        return
    responses.setdefault(
        str(code),
        {
            "description": _DESCRIPTIONS[code],
            "content": {"application/json": {"schema": _ERROR_SCHEMA}},
        },
    )
