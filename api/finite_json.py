"""Refuse JSON bodies holding numbers that are not finite, before any route sees them.

Python's JSON parser, which FastAPI uses, accepts ``NaN``, ``Infinity`` and ``-Infinity``, and
reads ``1e999`` as infinity; pydantic's float fields accept both, and a value that is not finite
then fails deep inside a computation or a response (HTTP 500). The HTTP guard
(:class:`api.security.SecurityGuard`) answers such a body with 422 in FastAPI's own validation
format, naming the field::

    {"detail": [{"type": "finite_number", "loc": ["body", "primitives", 0, "radius"],
                 "msg": "Input should be a finite number", "input": "inf"}]}

A body is parsed here only when its bytes could hold such a number
(:func:`could_hold_non_finite`), so ordinary bodies cost one scan.
"""

import json
import math
from typing import Any

from starlette.types import Send

__all__ = ["could_hold_non_finite", "is_json", "non_finite_errors", "non_finite_numbers", "reply"]

_DIGITS_AS_ZERO = bytes.maketrans(b"123456789E", b"000000000e")
_LONG_RUN = 300
_ZEROS = b"0" * _LONG_RUN
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


def is_json(content_type: bytes | None) -> bool:
    """True for a ``Content-Type`` of ``application/json`` or ``application/*+json``.

    >>> is_json(b"application/json; charset=utf-8"), is_json(b"text/plain"), is_json(None)
    (True, False, False)
    """
    if content_type is None:
        return False
    media = content_type.split(b";", 1)[0].strip().lower()
    return media == b"application/json" or media.endswith(b"+json")


def could_hold_non_finite(body: bytes) -> bool:
    """True if ``body`` holds ``NaN``, ``Infinity``, an exponent of three digits or more, or a
    run of 300 digits: the only ways JSON can spell a number that is not finite.

    As fast as a few substring searches: digits are mapped to ``0`` and signs dropped first, so
    that every exponent of three digits reads ``e000`` (a regular expression is several times
    slower on a directive's body).

    >>> could_hold_non_finite(b'{"x": 1e999}'), could_hold_non_finite(b'{"x": 1.5e-7}')
    (True, False)
    """
    digits = body.translate(_DIGITS_AS_ZERO, b"+-")
    return (
        b"e000" in digits
        or b"NaN" in body
        or b"Infinity" in body
        or (len(body) >= _LONG_RUN and _ZEROS in digits)
    )


def non_finite_errors(body: bytes) -> list[dict[str, Any]]:
    """FastAPI's validation errors (``finite_number``) for every number in the JSON ``body``
    that is not finite; empty for a body without any, or that is not JSON at all (its route
    answers that as usual).

    >>> [e["loc"] for e in non_finite_errors(b'{"a": [1, NaN]}')]
    [['body', 'a', 1]]
    """
    if not could_hold_non_finite(body):
        return []
    try:
        parsed = json.loads(body)
    except ValueError:
        return []
    return [
        {
            "type": "finite_number",
            "loc": ["body", *location],
            "msg": "Input should be a finite number",
            "input": str(value),
        }
        for location, value in non_finite_numbers(parsed)
    ]


async def reply(send: Send, errors: list[dict[str, Any]]) -> None:
    """Answer 422 with ``errors`` in FastAPI's validation format."""
    body = json.dumps({"detail": errors}).encode()
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
