"""ARMOR's two ROS services over HTTP, JSON field for field the ROS messages.

``?values=plain`` (IRIs without brackets, bare literal values) or ``?values=short`` (local names)
opts out of ARMOR's string formats for query results.

Directives are many and small, so the two services are mounted once, by :func:`install`, as the
app's innermost middleware (:class:`ArmorMiddleware`), in front of FastAPI's exception middleware
and router rather than as routes behind them. Every request to a service's path, whatever its
method or body, is answered there, and nowhere else:

- ``POST``: the bearer token (:func:`api.deps.require_token`, before reading the body), the body,
  :func:`api.directives.answer` (quick directives on the event loop, the rest in a worker thread),
  the answer's bytes;
- any other method: 405 with ``Allow: POST``; the path with trailing slashes: a 307 redirect to
  the path without them; as Starlette's router answers both.

Errors are answered by the app's exception handlers, as for a route (FastAPI's own 401, 405 and
422 shapes, the domain errors of ``api/errors.py``); an error no handler takes goes on to the
server error middleware (500). Being inside the user middleware, the services keep what it
does (the host and cross-site checks, body limits, security headers of :mod:`api.security`).
FastAPI cannot describe them, so :func:`install` adds their OpenAPI operations, built from the
same pydantic models, to the app's description. Dependency overrides do not reach them: they
have no FastAPI dependencies.
"""

from collections.abc import Callable
from typing import Any

from fastapi import FastAPI
from fastapi.openapi.utils import validation_error_definition, validation_error_response_definition
from fastapi.telemetry._api import _route_selected
from pydantic import TypeAdapter
from pydantic.json_schema import models_json_schema
from starlette.datastructures import URL
from starlette.exceptions import HTTPException
from starlette.middleware.exceptions import ExceptionMiddleware
from starlette.responses import RedirectResponse
from starlette.types import ASGIApp, Receive, Scope, Send

from api.config import Settings
from api.deps import require_token
from api.directives import SERVICES, VALUES, Service, answer

__all__ = ["ArmorMiddleware", "install", "openapi_operation"]

_REF = "#/components/schemas/{model}"
_JSON = (b"content-type", b"application/json")
_ALLOW = {"Allow": "POST"}


class ArmorMiddleware:
    """ASGI middleware answering every request to the services' paths (see the module
    docstring); other requests go on to ``app``.

    Reads the settings and the directive engine from the FastAPI app serving the request
    (``app.state.settings`` and ``app.state.services.armor``) and answers errors with its
    exception handlers.
    """

    def __init__(self, app: ASGIApp) -> None:
        self.app = app

    async def __call__(self, scope: Scope, receive: Receive, send: Send) -> None:
        service = SERVICES.get(_route_path(scope)) if scope["type"] == "http" else None
        if service is None:
            await self._elsewhere(scope, receive, send)
            return
        if "fastapi.telemetry" in scope:  # the span's route, as FastAPI's router names it
            _route_selected(scope=scope, path=service.path)
        try:
            if scope["method"] != "POST":
                raise HTTPException(405, headers=_ALLOW)
            content = await _content(service, scope, receive)
        except Exception as error:
            await _handle(error, scope, receive, send)
            return
        if content is None:
            return  # the client left: nobody to answer
        headers = [(b"content-length", str(len(content)).encode()), _JSON]
        await send({"type": "http.response.start", "status": 200, "headers": headers})
        await send({"type": "http.response.body", "body": content})

    async def _elsewhere(self, scope: Scope, receive: Receive, send: Send) -> None:
        """A request for another path: a service's path with trailing slashes is redirected
        to it, as Starlette's router does (``redirect_slashes``); the rest goes on."""
        if scope["type"] == "http" and scope["path"].endswith("/"):
            redirect = {**scope, "path": scope["path"].rstrip("/")}
            service = SERVICES.get(_route_path(redirect))
            if service is not None:
                if "fastapi.telemetry" in scope:
                    _route_selected(scope=scope, path=service.path)
                await RedirectResponse(str(URL(scope=redirect)))(scope, receive, send)
                return
        await self.app(scope, receive, send)


def _route_path(scope: Scope) -> str:
    """The request's path within the app: without the ``root_path`` it is mounted under, as
    Starlette's router matches routes."""
    path: str = scope["path"]
    root_path: str = scope.get("root_path", "")
    if not root_path or not path.startswith(root_path):
        return path
    if path == root_path:
        return ""
    return path[len(root_path) :] if path[len(root_path)] == "/" else path


async def _content(service: Service, scope: Scope, receive: Receive) -> bytes | None:
    """The answer's body to a ``POST`` to ``service``, None if the client left before sending
    all of its body. Raises :class:`~fastapi.HTTPException` (401) for a missing or wrong token
    and what :func:`~api.directives.answer` raises."""
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
        return None
    return await answer(
        state.services.armor,
        service,
        body,
        query=scope["query_string"],
        content_type=content_type,
    )


async def _handle(error: Exception, scope: Scope, receive: Receive, send: Send) -> None:
    """Answer ``error`` with the app's exception handlers, as its exception middleware does for
    an error raised by a route; raise it on if none takes it."""
    app = scope["app"]
    handlers = {k: v for k, v in app.exception_handlers.items() if k not in (500, Exception)}

    async def raise_it(scope: Scope, receive: Receive, send: Send) -> None:
        raise error

    await ExceptionMiddleware(raise_it, handlers=handlers, debug=app.debug)(scope, receive, send)


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
    """Mount the two services on ``app`` as :class:`ArmorMiddleware`, the innermost of its user
    middleware (call before adding any other), and describe them in its OpenAPI description."""
    app.add_middleware(ArmorMiddleware)
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
