"""ARMOR's two ROS services as functions from a request body (bytes) to a response body (bytes).

Every caller of the directive engine goes through here: the HTTP endpoints
(:mod:`api.routes.armor`), the in-process transport of the Python client
(:class:`api.client.LocalTransport`) and the ROS node. Each gives the body it received, the
URL's query string (``values=armor|plain|short``) and the body's content type, and gets back the
JSON body of the answer, written by pydantic once.

A request is read as FastAPI reads a route's JSON body parameter, and a bad one raises the error
FastAPI would, which FastAPI's handlers answer in its own shapes:

- :class:`~fastapi.exceptions.RequestValidationError` (422) for a body that is not JSON, does
  not validate, or is missing, and for a ``values`` that is not one of the three, with every
  error's ``loc`` starting ``"body"`` or ``"query"``;
- :class:`~fastapi.HTTPException` (400) for a body that cannot be decoded at all.

Errors of the engine (a list longer than the limit, the store failing) are raised on, for the
caller's error handling (``api/errors.py`` over HTTP).

>>> from kg import Store
>>> engine = ArmorEngine(Store())
>>> body = (b'{"armor_request": {"reference_name": "r", "command": "GET", '
...         b'"primary_command_spec": "ALL", "secondary_command_spec": "REFS"}}')
>>> answer_blocking(engine, SINGLE, body)[:49]
b'{"armor_response":{"success":true,"timeout":false'
"""

import email.message
import json
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Annotated, Any

from fastapi import HTTPException
from fastapi.exceptions import RequestValidationError
from pydantic import BaseModel, Field, TypeAdapter, ValidationError
from starlette.concurrency import run_in_threadpool
from starlette.datastructures import QueryParams

from api.armor import ArmorEngine
from api.armor.names import ValueStyle
from api.protocol import (
    ArmorDirectiveListReq,
    ArmorDirectiveListRes,
    ArmorDirectiveReq,
    ArmorRequest,
    ArmorResponse,
)

__all__ = [
    "LIST",
    "SERVICES",
    "SINGLE",
    "VALUES",
    "DirectiveCall",
    "Service",
    "answer",
    "answer_blocking",
    "read_request",
]

JSON = "application/json"

VALUES: TypeAdapter[ValueStyle] = TypeAdapter(
    Annotated[
        ValueStyle,
        Field(
            title="Values",
            description=(
                "How query results are written: ARMOR's strings, plain values, short names"
            ),
        ),
    ]
)
"""The ``values`` query parameter: how query results are written (default ``armor``)."""

_LIST_ON_LOOP = 8
"""Longest list of quick reads answered on the event loop."""
_SINGLE_OPEN = b'{"armor_response":'
_NO_BODY = object()
_COMMON_QUERIES: dict[bytes, ValueStyle] = {
    b"": "armor",
    b"values=armor": "armor",
    b"values=plain": "plain",
    b"values=short": "short",
}


@dataclass(frozen=True)
class Service:
    """One of ARMOR's two services: its path, its request and response models, its words."""

    path: str
    request: type[BaseModel]
    response: type[BaseModel]
    summary: str
    description: str

    @property
    def name(self) -> str:
        """The ROS service's name, as in the path."""
        return self.path.lstrip("/")


SINGLE = Service(
    "/armor_interface_srv",
    ArmorRequest,
    ArmorResponse,
    "One ARMOR directive",
    "``armor_msgs/ArmorDirective``: every protocol outcome, failures included, answers 200.",
)
LIST = Service(
    "/armor_interface_serialized_srv",
    ArmorDirectiveListReq,
    ArmorDirectiveListRes,
    "A list of ARMOR directives",
    "``armor_msgs/ArmorDirectiveList``: in order, one transaction, one response each.",
)
SERVICES: dict[str, Service] = {service.path: service for service in (SINGLE, LIST)}
"""The services by path."""


@dataclass(frozen=True)
class DirectiveCall:
    """A request that was read: the directives to run and how to write their results."""

    service: Service
    directives: Sequence[ArmorDirectiveReq]
    values: ValueStyle


def read_request(
    service: Service, body: bytes, *, query: bytes | str = b"", content_type: str | None = JSON
) -> DirectiveCall:
    """The directives in ``body`` and the ``values`` style in ``query``.

    Raises :class:`~fastapi.exceptions.RequestValidationError` or
    :class:`~fastapi.HTTPException` (400) as FastAPI would for a route taking the service's
    request model as its body and ``values`` as a query parameter (see the module docstring).
    """
    values = _COMMON_QUERIES.get(query.encode("latin-1") if isinstance(query, str) else query)
    parsed = None
    if values is not None and body and _is_json(content_type):
        # the usual case, straight from the bytes; otherwise read again below, as FastAPI
        # does, for its error answers
        try:
            parsed = service.request.model_validate_json(body)
        except ValidationError:
            parsed = None
    if parsed is None or values is None:
        values, parsed = _read_slowly(service, body, query, content_type)
    if isinstance(parsed, ArmorRequest):
        return DirectiveCall(service, [parsed.armor_request], values)
    assert isinstance(parsed, ArmorDirectiveListReq)
    return DirectiveCall(service, parsed.armor_requests, values)


async def answer(
    engine: ArmorEngine,
    service: Service,
    body: bytes,
    *,
    query: bytes | str = b"",
    content_type: str | None = JSON,
) -> bytes:
    """The JSON body answering ``body`` sent to ``service``, for a caller on an event loop.

    A directive that cannot be made to wait runs on the event loop, since it costs less than the
    trip to a worker thread (:meth:`~api.armor.ArmorEngine.execute_now`): a query that reads a
    few triples (every QUERY but QUERY SPARQL; it takes no lock), a list of at most eight of
    them, and a simple write (ADD, REMOVE, REPLACE, DISJOINT IND) to a reference that reasons
    only on REASON, when no other list is running and the reference's lock is free. Everything
    else (SPARQL, REASON, LOAD, SAVE, the memory pipeline, lists with writes, any write that
    might wait) runs in a worker thread, so that it never holds up other requests.

    Raises what :func:`read_request` raises, and the engine's errors.
    """
    call = read_request(service, body, query=query, content_type=content_type)
    engine_now = _answer_now(engine, call)
    if engine_now is not None:
        return engine_now
    return await run_in_threadpool(_answer, engine, call)


def answer_blocking(
    engine: ArmorEngine,
    service: Service,
    body: bytes,
    *,
    query: bytes | str = b"",
    content_type: str | None = JSON,
) -> bytes:
    """The JSON body answering ``body`` sent to ``service``, in the calling thread (for callers
    that are not on an event loop: the client's local transport, a ROS service callback).

    Raises what :func:`read_request` raises, and the engine's errors.
    """
    return _answer(engine, read_request(service, body, query=query, content_type=content_type))


def _answer_now(engine: ArmorEngine, call: DirectiveCall) -> bytes | None:
    """The answer, if it could be given without waiting; None (nothing done) otherwise."""
    if call.service is SINGLE:
        response = engine.execute_now(call.directives[0], style=call.values)
        return None if response is None else _single(response)
    directives = call.directives
    if len(directives) <= _LIST_ON_LOOP and all(engine.is_quick_read(d) for d in directives):
        return _answer(engine, call)
    return None


def _answer(engine: ArmorEngine, call: DirectiveCall) -> bytes:
    if call.service is SINGLE:
        return _single(engine.execute(call.directives[0], style=call.values))
    result = engine.execute_list(call.directives, style=call.values)
    return result.__pydantic_serializer__.to_json(result)


def _single(response: BaseModel) -> bytes:
    # ArmorResponse(armor_response=response).model_dump_json(), without building the wrapper
    return b"".join((_SINGLE_OPEN, response.__pydantic_serializer__.to_json(response), b"}"))


def _is_json(content_type: str | None) -> bool:
    """True for ``application/json`` and ``application/*+json``, parameters aside, as FastAPI
    decides whether a body is JSON."""
    if not content_type:
        return False
    if content_type.partition(";")[0].strip().lower() == JSON:  # the usual case, quickly
        return True
    message = email.message.Message()
    message["content-type"] = content_type
    subtype = message.get_content_subtype()
    return message.get_content_maintype() == "application" and (
        subtype == "json" or subtype.endswith("+json")
    )


def _read_slowly(
    service: Service, body: bytes, query: bytes | str, content_type: str | None
) -> tuple[ValueStyle, BaseModel]:
    """Read the request as FastAPI does: JSON decoded by Python's parser, then the query and the
    body validated, every error of both reported at once."""
    content: Any = _NO_BODY
    if body:
        if _is_json(content_type):
            try:
                content = json.loads(body)
            except json.JSONDecodeError as error:
                decode_error = {
                    "type": "json_invalid",
                    "loc": ("body", error.pos),
                    "msg": "JSON decode error",
                    "input": {},
                    "ctx": {"error": error.msg},
                }
                raise RequestValidationError([decode_error], body=error.doc) from error
            except Exception as error:  # not UTF-8 (nor 16 nor 32), nested too deep
                raise HTTPException(400, "There was an error parsing the body") from error
        else:
            content = body  # not JSON: FastAPI validates the bytes, and says so
    errors: list[Any] = []
    values: ValueStyle = "armor"
    given = QueryParams(query).get("values")
    if given is not None:
        try:
            values = VALUES.validate_python(given)
        except ValidationError as error:
            errors += _located(error, ("query", "values"))
    parsed: BaseModel | None = None
    if content is _NO_BODY:
        errors.append({"type": "missing", "loc": ("body",), "msg": "Field required", "input": None})
    else:
        try:
            parsed = service.request.model_validate(content, from_attributes=True)
        except ValidationError as error:
            errors += _located(error, ("body",))
    if errors:
        raise RequestValidationError(errors, body=None if content is _NO_BODY else content)
    assert parsed is not None
    return values, parsed


def _located(error: ValidationError, prefix: tuple[str, ...]) -> list[Any]:
    return [{**e, "loc": (*prefix, *e["loc"])} for e in error.errors(include_url=False)]
