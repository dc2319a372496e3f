"""A time limit on a request's headers, which uvicorn does not have.

Uvicorn closes a connection left idle after a response (``timeout_keep_alive``), but waits for
ever for a request that has begun and not finished its headers, and for the first request of a
new connection: a client can hold connections open by sending a byte now and then. The
protocol :func:`with_header_timeout` makes (uvicorn's own httptools protocol with a timer)
closes a connection whose request headers are not complete ``timeout_s`` after the connection
was made or the request began. The body's own limit is the HTTP guard's (``api/security.py``).

Used as ``uvicorn.run(app, http=with_header_timeout(settings.header_timeout_s))``.
"""

import asyncio
import logging
from typing import Any

from uvicorn.protocols.http.httptools_impl import HttpToolsProtocol

__all__ = ["with_header_timeout"]

log = logging.getLogger(__name__)


class _HeaderTimeoutProtocol(HttpToolsProtocol):
    """Uvicorn's httptools protocol, closing connections whose headers stall."""

    header_timeout_s = 10.0

    def __init__(self, *args: Any, **kwargs: Any) -> None:
        super().__init__(*args, **kwargs)
        self._header_timer: asyncio.TimerHandle | None = None

    def connection_made(self, transport: asyncio.Transport) -> None:  # type: ignore[override]
        super().connection_made(transport)
        self._arm()

    def connection_lost(self, exc: Exception | None) -> None:
        self._disarm()
        super().connection_lost(exc)

    def on_message_begin(self) -> None:
        super().on_message_begin()
        self._arm()

    def on_headers_complete(self) -> None:
        self._disarm()
        super().on_headers_complete()

    def _arm(self) -> None:
        self._disarm()
        self._header_timer = self.loop.call_later(self.header_timeout_s, self._headers_late)

    def _disarm(self) -> None:
        if self._header_timer is not None:
            self._header_timer.cancel()
            self._header_timer = None

    def _headers_late(self) -> None:
        self._header_timer = None
        log.info("closing a connection whose request headers took over %g s", self.header_timeout_s)
        if not self.transport.is_closing():
            self.transport.write(
                b"HTTP/1.1 408 Request Timeout\r\ncontent-type: text/plain\r\n"
                b"content-length: 37\r\nconnection: close\r\n\r\n"
                b"request headers: not received in time"
            )
            self.transport.close()


def with_header_timeout(timeout_s: float) -> type[HttpToolsProtocol]:
    """Uvicorn's HTTP protocol (``http=``), closing with 408 a connection whose request headers
    are not complete ``timeout_s`` seconds after it was made or its request began."""
    if not timeout_s > 0:
        raise ValueError(f"timeout_s: got {timeout_s}, expected a positive number of seconds")
    return type("HeaderTimeoutProtocol", (_HeaderTimeoutProtocol,), {"header_timeout_s": timeout_s})
