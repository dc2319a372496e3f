"""The ARMOR endpoints' short path: a raw ASGI layer ahead of FastAPI's router.

Directives are many and small: FastAPI's exception middleware, router, route matching, request
object and dependency solving cost about as much as a simple directive does in the engine. So
:class:`ArmorFastPath`, installed by :func:`install` as the app's outermost user middleware,
answers a well-formed ``POST /armor_interface_srv`` or ``/armor_interface_serialized_srv``
itself:

- ``Content-Type: application/json``, a query string that is empty or exactly
  ``values=armor|plain|short``, the bearer token if one is set, a body pydantic validates
  straight from the bytes;
- the directive runs as the usual route runs it (:func:`api.routes.armor.answer_single`), and the
  answer is written by pydantic once, as bytes, with the usual headers.

Anything else (another content type, a malformed or empty body, a bad ``values``, a missing or
wrong token, an unusual query string, a client that disconnects while sending) goes on to
FastAPI's usual stack with the body bytes already received replayed, so that every error (422,
400, 401, 404, 405...) is FastAPI's own. The path is off, and every request takes the usual one,
when a request body size limit applies to the ARMOR routes or dependency overrides are set
(tests), since it honours neither. An exception escaping the engine goes to the app's exception
handlers as it would from the route, then to the server error middleware.

Being inside the server error, telemetry and body limit middleware, the path keeps what they do.
"""

import logging
from collections.abc import Awaitable, Callable
from typing import Any

from fastapi import FastAPI, HTTPException
from pydantic import BaseModel, ValidationError
from starlette.middleware.exceptions import ExceptionMiddleware
from starlette.types import ASGIApp, Message, Receive, Scope, Send

from api.armor import ArmorEngine
from api.armor.models import ArmorDirectiveListReq, ArmorRequest
from api.armor.names import ValueStyle
from api.config import Settings
from api.deps import require_token
from api.routes import armor

__all__ = ["ArmorFastPath", "install"]

log = logging.getLogger(__name__)

Answer = Callable[[ArmorEngine, Any, ValueStyle], Awaitable[bytes]]

_PATHS: dict[str, tuple[type[BaseModel], Answer]] = {
    "/armor_interface_srv": (
        ArmorRequest,
        lambda engine, body, values: armor.answer_single(engine, body.armor_request, values),
    ),
    "/armor_interface_serialized_srv": (
        ArmorDirectiveListReq,
        lambda engine, body, values: armor.answer_list(engine, body.armor_requests, values),
    ),
}
_QUERIES: dict[bytes, ValueStyle] = {
    b"": "armor",
    b"values=armor": "armor",
    b"values=plain": "plain",
    b"values=short": "short",
}
_JSON = (b"content-type", b"application/json")


def install(app: FastAPI) -> None:
    """Put the short path ahead of ``app``'s router (call before the app first serves)."""
    app.add_middleware(ArmorFastPath, fastapi=app)


def _limited(app: FastAPI) -> bool:
    """True if a request body size limit may apply to the ARMOR routes."""
    if app.max_body_size is not None or app.router.max_body_size is not None:
        return True
    for route in app.router.routes:
        if getattr(route, "original_router", None) is armor.router:
            context = getattr(route, "include_context", None)
            if context is None or context.max_body_size is not None or context.prefix:
                return True
    if armor.router.max_body_size is not None:
        return True
    return any(getattr(route, "max_body_size", None) is not None for route in armor.router.routes)


class ArmorFastPath:
    """ASGI middleware answering well-formed ARMOR requests (see the module docstring)."""

    def __init__(self, app: ASGIApp, *, fastapi: FastAPI) -> None:
        self.app = app
        self.fastapi = fastapi
        self.enabled = not _limited(fastapi)
        if not self.enabled:
            log.info("a body size limit applies to the ARMOR routes: their short path is off")
        handlers = {
            key: value
            for key, value in fastapi.exception_handlers.items()
            if key not in (500, Exception)  # the server error middleware's, outside this one
        }
        self._handlers = handlers

    async def __call__(self, scope: Scope, receive: Receive, send: Send) -> None:
        route = _PATHS.get(scope["path"]) if scope["type"] == "http" else None
        if (
            route is None
            or not self.enabled
            or scope["method"] != "POST"
            or scope.get("root_path")
            or self.fastapi.dependency_overrides
        ):
            await self.app(scope, receive, send)
            return
        values = _QUERIES.get(scope["query_string"])
        content_type = authorization = None
        for name, value in scope["headers"]:
            if name == b"content-type":
                content_type = value
            elif name == b"authorization":
                authorization = value
        if (
            values is None
            or content_type is None
            or content_type.partition(b";")[0].strip().lower() != b"application/json"
        ):
            await self.app(scope, receive, send)
            return
        state = self.fastapi.state
        settings: Settings = state.settings
        if settings.token is not None:
            try:
                await require_token(
                    settings, None if authorization is None else authorization.decode("latin-1")
                )
            except HTTPException:
                await self.app(scope, receive, send)
                return
        messages: list[Message] = []
        chunks: list[bytes] = []
        while True:
            message = await receive()
            messages.append(message)
            if message["type"] != "http.request":  # the client left: the usual path says so
                await self.app(scope, _replay(messages, receive), send)
                return
            chunks.append(message.get("body", b""))
            if not message.get("more_body", False):
                break
        body = chunks[0] if len(chunks) == 1 else b"".join(chunks)
        model, answer = route
        try:
            parsed = model.model_validate_json(body) if body else None
        except ValidationError:
            parsed = None
        if parsed is None:
            await self.app(scope, _replay(messages, receive), send)
            return
        try:
            content = await answer(state.services.armor, parsed, values)
        except Exception as error:
            await self._error(error, scope, _replay(messages, receive), send)
            return
        headers = [(b"content-length", str(len(content)).encode()), _JSON]
        await send({"type": "http.response.start", "status": 200, "headers": headers})
        await send({"type": "http.response.body", "body": content})

    async def _error(self, error: Exception, scope: Scope, receive: Receive, send: Send) -> None:
        """Answer ``error`` as the app's exception handlers would, else raise it on."""

        async def reraise(scope: Scope, receive: Receive, send: Send) -> None:
            raise error

        handling = ExceptionMiddleware(reraise, handlers=self._handlers, debug=self.fastapi.debug)
        await handling(scope, receive, send)


def _replay(messages: list[Message], receive: Receive) -> Receive:
    """``receive`` that first gives back ``messages`` (already read), in order."""
    pending = list(messages)

    async def replay() -> Message:
        if pending:
            return pending.pop(0)
        return await receive()

    return replay
