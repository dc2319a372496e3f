"""ARMOR's two ROS services over HTTP, JSON field for field the ROS messages.

``?values=plain`` (IRIs without brackets, bare literal values) or ``?values=short`` (local names)
opts out of ARMOR's string formats for query results.

Directives are many and small, so each service is a plain ASGI endpoint rather than a FastAPI
route: it checks the bearer token (:func:`api.deps.require_token`, before reading the body),
reads the body, hands it to :func:`api.directives.answer`, which answers quick directives on the
event loop and the rest in a worker thread, and writes the answer's bytes. It sits inside the
app's middleware and exception handlers like any route, so a body size limit, the error answers
(FastAPI's own 401, 405 and 422 shapes, the domain errors of ``api/errors.py``) and the server
error middleware apply to it. FastAPI cannot describe an ASGI endpoint, so :func:`install` adds
its OpenAPI operations, built from the same pydantic models, to the app's description.
Dependency overrides do not reach it: it has no FastAPI dependencies.
"""

from collections.abc import Callable
from typing import Any

from fastapi import FastAPI
from fastapi.openapi.utils import validation_error_definition, validation_error_response_definition
from pydantic import TypeAdapter
from pydantic.json_schema import models_json_schema
from starlette.routing import Route
from starlette.types import Receive, Scope, Send

from api.config import Settings
from api.deps import require_token
from api.directives import SERVICES, VALUES, Service, answer

__all__ = ["DirectiveEndpoint", "install", "openapi_operation"]

_REF = "#/components/schemas/{model}"
_JSON = (b"content-type", b"application/json")


class DirectiveEndpoint:
    """The ASGI endpoint of one service: token, body, :func:`api.directives.answer`, bytes.

    Reads the settings and the directive engine from the app (``app.state.settings`` and
    ``app.state.services.armor``). Raises :class:`~fastapi.HTTPException` (401) for a missing or
    wrong token and what :func:`~api.directives.answer` raises, for the app's handlers.
    """

    def __init__(self, service: Service) -> None:
        self.service = service

    async def __call__(self, scope: Scope, receive: Receive, send: Send) -> None:
        state = scope["app"].state
        content_type = authorization = None
        for name, value in scope["headers"]:  # the first of each, as Starlette reads headers
            if name == b"content-type" and content_type is None:
                content_type = value.decode("latin-1")
            elif name == b"authorization" and authorization is None:
                authorization = value.decode("latin-1")
        settings: Settings = state.settings
        if settings.token is not None:
            await require_token(settings, authorization)
        body = await _body(receive)
        if body is None:
            return  # the client left: nobody to answer
        content = await answer(
            state.services.armor,
            self.service,
            body,
            query=scope["query_string"],
            content_type=content_type,
        )
        headers = [(b"content-length", str(len(content)).encode()), _JSON]
        await send({"type": "http.response.start", "status": 200, "headers": headers})
        await send({"type": "http.response.body", "body": content})


async def _body(receive: Receive) -> bytes | None:
    """The request body, or None if the client disconnected before sending all of it."""
    chunks: list[bytes] = []
    while True:
        message = await receive()
        if message["type"] != "http.request":
            return None
        chunks.append(message.get("body", b""))
        if not message.get("more_body", False):
            return chunks[0] if len(chunks) == 1 else b"".join(chunks)


def openapi_operation(service: Service) -> dict[str, Any]:
    """The OpenAPI operation of ``service``'s ``POST``, as FastAPI would write it for a route
    with its request model as body, ``values`` as query parameter and the token header."""
    values = VALUES.json_schema()
    authorization = TypeAdapter(str | None).json_schema()
    return {
        "tags": ["armor"],
        "summary": service.summary,
        "description": service.description,
        "operationId": f"{service.name}_{service.name}_post",
        "parameters": [
            {
                "name": "values",
                "in": "query",
                "required": False,
                "schema": {**values, "default": "armor"},
                "description": values["description"],
            },
            {
                "name": "authorization",
                "in": "header",
                "required": False,
                "schema": {**authorization, "title": "Authorization"},
            },
        ],
        "requestBody": {
            "required": True,
            "content": {"application/json": {"schema": _ref(service.request)}},
        },
        "responses": {
            "200": {
                "description": "Successful Response",
                "content": {"application/json": {"schema": _ref(service.response)}},
            },
            "422": {
                "description": "Validation Error",
                "content": {
                    "application/json": {
                        "schema": {"$ref": _REF.format(model="HTTPValidationError")}
                    }
                },
            },
        },
    }


def _ref(model: type) -> dict[str, str]:
    return {"$ref": _REF.format(model=model.__name__)}


def _schemas() -> dict[str, Any]:
    """The JSON schemas of the services' models and of FastAPI's validation error answer."""
    models = [(s.request, "validation") for s in SERVICES.values()]
    models += [(s.response, "serialization") for s in SERVICES.values()]
    _, top = models_json_schema(models, ref_template=_REF)  # type: ignore[arg-type]
    return {
        **top.get("$defs", {}),
        "ValidationError": validation_error_definition,
        "HTTPValidationError": validation_error_response_definition,
    }


def install(app: FastAPI) -> None:
    """Mount the two services on ``app`` ahead of its other routes (route matching is a
    sizeable share of a directive's time), and describe them in its OpenAPI description."""
    for index, service in enumerate(SERVICES.values()):
        route = Route(service.path, DirectiveEndpoint(service), methods=["POST"], name=service.name)
        app.router.routes.insert(index, route)
    original: Callable[[], dict[str, Any]] = app.openapi

    def openapi() -> dict[str, Any]:
        if app.openapi_schema is not None:
            return app.openapi_schema
        spec = original()
        operations = {s.path: {"post": openapi_operation(s)} for s in SERVICES.values()}
        spec["paths"] = {**operations, **spec.get("paths", {})}
        schemas = spec.setdefault("components", {}).setdefault("schemas", {})
        for name, schema in _schemas().items():
            schemas.setdefault(name, schema)
        spec["components"]["schemas"] = dict(sorted(schemas.items()))
        app.openapi_schema = spec
        return spec

    app.openapi = openapi  # type: ignore[method-assign]
