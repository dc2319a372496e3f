"""Refuse JSON bodies holding numbers that are not finite, before any route sees them.

Python's JSON parser, which FastAPI uses, accepts ``NaN``, ``Infinity`` and ``-Infinity``, and
reads ``1e999`` as infinity; pydantic's float fields accept both, and a value that is not finite
then fails deep inside a computation or a response (HTTP 500). :class:`FiniteJsonBodies` answers
such a body with 422 in FastAPI's own validation format, naming the field::

    {"detail": [{"type": "finite_number", "loc": ["body", "primitives", 0, "radius"],
                 "msg": "Input should be a finite number", "input": "inf"}]}

A body is parsed here only when its bytes could hold such a number (``NaN``, ``Infinity``, an
exponent of three digits or more, or a run of 300 digits), so ordinary bodies cost one scan.
"""

import json
import math
import re
from typing import Any

from starlette.types import ASGIApp, Message, Receive, Scope, Send

__all__ = ["FiniteJsonBodies", "non_finite_numbers"]

_SUSPECT = re.compile(rb"NaN|Infinity|[eE][+-]?\d{3}|\d{300}")
Location = list[str | int]


def non_finite_numbers(value: Any, location: Location | None = None) -> list[tuple[Location, Any]]:
    """The location and value of every number in a parsed JSON value that is not finite.

    >>> non_finite_numbers({"a": [1.0, float("nan")], "b": {"c": float("inf")}})
    [(['a', 1], nan), (['b', 'c'], inf)]
    """
    location = location or []
    if isinstance(value, float):
        return [] if math.isfinite(value) else [(location, value)]
    if isinstance(value, dict):
        return [
            f for key, item in value.items() for f in non_finite_numbers(item, [*location, key])
        ]
    if isinstance(value, list):
        return [f for i, item in enumerate(value) for f in non_finite_numbers(item, [*location, i])]
    return []


def _is_json(scope: Scope) -> bool:
    for name, value in scope.get("headers", ()):
        if name == b"content-type":
            media: bytes = value.split(b";")[0].strip().lower()
            return media == b"application/json" or media.endswith(b"+json")
    return False


class FiniteJsonBodies:
    """ASGI middleware: a JSON request body with a non-finite number answers 422."""

    def __init__(self, app: ASGIApp) -> None:
        self.app = app

    async def __call__(self, scope: Scope, receive: Receive, send: Send) -> None:
        if scope["type"] != "http" or not _is_json(scope):
            await self.app(scope, receive, send)
            return
        messages: list[Message] = []
        chunks: list[bytes] = []
        while True:
            message = await receive()
            messages.append(message)
            if message["type"] != "http.request":
                break
            chunks.append(message.get("body", b""))
            if not message.get("more_body", False):
                break
        body = b"".join(chunks)
        if _SUSPECT.search(body):
            errors = _errors(body)
            if errors:
                await _reply(send, {"detail": errors})
                return

        async def replay() -> Message:
            return messages.pop(0) if messages else await receive()

        await self.app(scope, replay, send)


def _errors(body: bytes) -> list[dict[str, Any]]:
    try:
        parsed = json.loads(body)
    except ValueError:
        return []  # malformed JSON: the route answers it as usual
    return [
        {
            "type": "finite_number",
            "loc": ["body", *location],
            "msg": "Input should be a finite number",
            "input": str(value),
        }
        for location, value in non_finite_numbers(parsed)
    ]


async def _reply(send: Send, content: dict[str, Any]) -> None:
    body = json.dumps(content).encode()
    await send(
        {
            "type": "http.response.start",
            "status": 422,
            "headers": [
                (b"content-type", b"application/json"),
                (b"content-length", str(len(body)).encode()),
            ],
        }
    )
    await send({"type": "http.response.body", "body": body})
