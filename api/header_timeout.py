"""Time limits on a request's headers and body, which uvicorn does not have.

Uvicorn closes a connection left idle after a response (``timeout_keep_alive``), but waits for
ever for a request that has begun and not finished its headers, for the first request of a new
connection, and for the rest of a body the client stops sending: a client can hold connections
open by sending a byte now and then. The protocol :func:`with_header_timeout` makes (uvicorn's
own httptools protocol with one timer per connection) answers 408 and closes the connection when

- a request's headers are not complete ``timeout_s`` after the connection was made or the
  request began;
- (with ``body_timeout_s``) the server is reading a request's body and no part of it has come
  for ``body_timeout_s``. Time during which the server is not reading (it has a full buffer
  the application has not taken yet, or the client awaits ``100 Continue``) does not count.

The checks cost a few attribute writes per request: the connection's one timer is armed once
and, when it fires before the deadline then current, re-armed for it (it is armed anew only
when a deadline comes sooner than the timer, as for a body limit below the headers' one).

Used as ``uvicorn.run(app, http=with_header_timeout(settings.header_timeout_s,
body_timeout_s=settings.body_timeout_s))``, as ``engram serve`` does.
"""

import asyncio
import json
import logging
from typing import Any

from uvicorn.protocols.http.httptools_impl import HttpToolsProtocol

__all__ = ["with_header_timeout"]

log = logging.getLogger(__name__)

_HEADERS_LATE = (
    b"HTTP/1.1 408 Request Timeout\r\ncontent-type: text/plain\r\n"
    b"content-length: 37\r\nconnection: close\r\n\r\n"
    b"request headers: not received in time"
)


def _body_late(timeout_s: float) -> bytes:
    """The 408 answer to a stalled body, in the JSON shape of the server's other refusals."""
    detail = f"request body: nothing received for {timeout_s:g} s"
    body = json.dumps({"detail": detail, "error": "BodyTimeoutError"}).encode()
    return (
        b"HTTP/1.1 408 Request Timeout\r\ncontent-type: application/json\r\n"
        b"content-length: %d\r\nconnection: close\r\n\r\n%s" % (len(body), body)
    )


class _TimedProtocol(HttpToolsProtocol):
    """Uvicorn's httptools protocol, closing connections whose headers or body stall."""

    header_timeout_s = 10.0
    body_timeout_s: float | None = None

    def __init__(self, *args: Any, **kwargs: Any) -> None:
        super().__init__(*args, **kwargs)
        self._timer: asyncio.TimerHandle | None = None
        self._deadline = 0.0
        self._awaiting: bytes | None = None  # b"headers", b"body" or None (nothing)

    def connection_made(self, transport: asyncio.Transport) -> None:  # type: ignore[override]
        super().connection_made(transport)
        self._await(b"headers", self.header_timeout_s)

    def connection_lost(self, exc: Exception | None) -> None:
        self._awaiting = None
        if self._timer is not None:
            self._timer.cancel()
            self._timer = None
        super().connection_lost(exc)

    def on_message_begin(self) -> None:
        super().on_message_begin()
        self._await(b"headers", self.header_timeout_s)

    def on_headers_complete(self) -> None:
        super().on_headers_complete()
        if self.body_timeout_s is None or self.parser.should_upgrade():
            self._awaiting = None  # (an upgrade hands the connection to another protocol)
        else:  # until on_message_complete, which follows at once for a request without body
            self._await(b"body", self.body_timeout_s)

    def on_body(self, body: bytes) -> None:
        super().on_body(body)
        if self._awaiting is not None:
            self._deadline = self.loop.time() + self.body_timeout_s  # type: ignore[operator]

    def on_message_complete(self) -> None:
        super().on_message_complete()
        self._awaiting = None

    def _await(self, what: bytes, timeout_s: float) -> None:
        """Expect ``what`` within ``timeout_s``; arm the timer unless it is due by then."""
        self._awaiting = what
        self._deadline = self.loop.time() + timeout_s
        if self._timer is not None and self._timer.when() > self._deadline:
            self._timer.cancel()  # due after the new deadline (a body limit below the headers')
            self._timer = None
        if self._timer is None:
            self._timer = self.loop.call_at(self._deadline, self._check)

    def _check(self) -> None:
        """The timer: re-arm for the current deadline, or answer 408 if it has passed."""
        self._timer = None
        if self._awaiting is None:
            return
        now = self.loop.time()
        if self._awaiting == b"body" and not self._reading_body():
            self._deadline = now + self.body_timeout_s  # type: ignore[operator]
        if now < self._deadline:
            self._timer = self.loop.call_at(self._deadline, self._check)
            return
        if self.transport.is_closing():
            return
        if self._awaiting == b"headers":
            log.info(
                "closing a connection whose request headers took over %g s", self.header_timeout_s
            )
            self.transport.write(_HEADERS_LATE)
        else:
            log.info(
                "closing a connection whose request body stalled for %g s", self.body_timeout_s
            )
            cycle = self.cycle
            if not cycle.response_started:
                self.transport.write(_body_late(self.body_timeout_s))  # type: ignore[arg-type]
            # the application's reads end as for a client that left, and its answer is dropped
            cycle.disconnected = True
            cycle.message_event.set()
        self._awaiting = None
        self.transport.close()

    def _reading_body(self) -> bool:
        """True if the client, not the server, is the one to move: the server reads."""
        return not (self.flow.read_paused or self.cycle.waiting_for_100_continue)


def with_header_timeout(
    timeout_s: float, *, body_timeout_s: float | None = None
) -> type[HttpToolsProtocol]:
    """Uvicorn's HTTP protocol (``http=``), closing with 408 a connection whose request headers
    are not complete ``timeout_s`` seconds after it was made or its request began, and (given
    ``body_timeout_s``) one whose request body stops coming for ``body_timeout_s`` seconds.

    Raises :class:`ValueError` for a timeout that is not a positive number of seconds.
    """
    for name, value in (("timeout_s", timeout_s), ("body_timeout_s", body_timeout_s)):
        if value is not None and not value > 0:
            raise ValueError(f"{name}: got {value}, expected a positive number of seconds")
    return type(
        "TimedProtocol",
        (_TimedProtocol,),
        {"header_timeout_s": timeout_s, "body_timeout_s": body_timeout_s},
    )
