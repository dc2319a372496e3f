"""The HTTP layer's guard against other sites, oversized bodies and numbers that are not finite.

:class:`SecurityGuard`, installed by :func:`install` as the app's outermost user middleware,
checks every HTTP request before any route sees it, in one layer:

- **Host.** The ``Host`` header must name this server (``Settings.allowed_hosts``; by default
  the loopback names, the listening address and this machine's host name), else 400. A page on
  another site that rebinds its DNS name to this machine still sends its own name.
- **Cross-site writes.** A request that may change state (any method but GET, HEAD, OPTIONS)
  whose ``Origin`` is neither this server's own nor in ``Settings.allowed_origins``, or whose
  ``Sec-Fetch-Site`` says ``cross-site`` or ``same-site``, answers 403, whether or not a token
  is set. Browsers send ``Origin`` with every cross-origin POST, even the ones that need no
  preflight (form-encoded, ``text/plain``, ``no-cors``); clients that are not browsers send
  neither header and are not affected.
- **Body size.** A body longer than its route's limit answers 413: at once when
  ``Content-Length`` says so, else as soon as the bytes received pass it.
- **Numbers that are not finite.** A JSON body holding ``NaN``, ``Infinity`` or a number too
  large for a float answers 422 naming the field (:mod:`api.finite_json`); a JSON body is read
  whole here for this, within its limit, and handed on in one message.

A client that stalls in its headers or body answers 408: that limit is the server protocol's
(``api/header_timeout.py``, used by ``engram serve``), which keeps a deadline per connection
instead of a timer per read.

Every answer carries a strict ``Content-Security-Policy`` (scripts only from this server, the
pages' own import map by its hash; no frames), ``X-Frame-Options: DENY``,
``X-Content-Type-Options: nosniff`` and ``Referrer-Policy: no-referrer``.
"""

import base64
import hashlib
import json
import logging
import os
import re
import socket
import tempfile
from collections.abc import AsyncIterator, Iterable, Mapping
from contextlib import asynccontextmanager
from pathlib import Path
from typing import Any
from urllib.parse import urlsplit

from fastapi import FastAPI, Request
from starlette.exceptions import HTTPException
from starlette.requests import ClientDisconnect
from starlette.types import ASGIApp, Message, Receive, Scope, Send

from api import finite_json
from api.armor.files import FileAccess
from api.config import Settings

__all__ = [
    "BodyTooLargeError",
    "SecurityGuard",
    "allowed_host_names",
    "armor_file_access",
    "content_security_policy",
    "install",
    "saved_body",
]

log = logging.getLogger(__name__)

SAFE_METHODS = frozenset({"GET", "HEAD", "OPTIONS"})
LOOPBACK_NAMES = ("localhost", "127.0.0.1", "::1")
_WILDCARD_ADDRESSES = {"0.0.0.0", "::", ""}
_SERVED_HOSTS_KEPT = 64
_WEB_DIR = Path(__file__).resolve().parent / "web"
_INLINE_SCRIPT = re.compile(r"<script(?![^>]*\bsrc=)[^>]*>(.*?)</script>", re.DOTALL)


class BodyTooLargeError(HTTPException):
    """The request body is longer than its route's limit (413)."""

    def __init__(self, limit: int, setting: str) -> None:
        super().__init__(413, f"request body: longer than the limit of {limit} bytes ({setting})")


def allowed_host_names(settings: Settings) -> frozenset[str] | None:
    """The host names the server answers to, lower case, or None for any (``'*'``).

    >>> sorted(allowed_host_names(Settings(allowed_hosts="robot.lan,10.0.0.7")))
    ['10.0.0.7', 'robot.lan']
    >>> allowed_host_names(Settings(allowed_hosts="*")) is None
    True
    """
    configured = [name.strip().lower() for name in settings.allowed_hosts.split(",")]
    configured = [name for name in configured if name]
    if "*" in configured:
        return None
    if configured:
        return frozenset(_bare(name) for name in configured)
    names = set(LOOPBACK_NAMES)
    if settings.host not in _WILDCARD_ADDRESSES:
        names.add(_bare(settings.host.lower()))
    hostname = socket.gethostname().lower()
    if hostname:
        names |= {hostname, f"{hostname}.local"}
    return frozenset(names)


def _bare(host: str) -> str:
    """A host without its brackets (``[::1]`` -> ``::1``)."""
    return host[1:-1] if host.startswith("[") and host.endswith("]") else host


def _host_of(authority: str) -> str:
    """The host of a ``Host`` header value (``name:port``, ``[v6]:port``), lower case."""
    authority = authority.strip().lower()
    if authority.startswith("["):
        return authority[1 : authority.find("]")] if "]" in authority else authority
    if authority.count(":") == 1:
        return authority.split(":", 1)[0]
    return authority


def content_security_policy(web_dir: Path = _WEB_DIR) -> str:
    """The pages' policy: everything from this server only, the inline scripts of the pages in
    ``web_dir`` (the import map) allowed by their SHA-256, no plugins, frames or foreign forms.

    Styles allow ``'unsafe-inline'``: the vendored graph and timeline libraries add ``<style>``
    elements and style attributes; styles cannot run script.
    """
    hashes = sorted(
        {
            "'sha256-" + base64.b64encode(hashlib.sha256(script.encode()).digest()).decode() + "'"
            for page in sorted(web_dir.glob("*.html"))
            for script in _INLINE_SCRIPT.findall(page.read_text(encoding="utf-8"))
        }
    )
    return "; ".join(
        [
            "default-src 'self'",
            " ".join(["script-src 'self'", *hashes]),
            "style-src 'self' 'unsafe-inline'",
            "img-src 'self' data: blob:",
            "worker-src 'self' blob:",
            "connect-src 'self'",
            "object-src 'none'",
            "base-uri 'none'",
            "form-action 'self'",
            "frame-ancestors 'none'",
        ]
    )


def _origin_authority(origin: str) -> str | None:
    """``host[:port]`` of an ``Origin`` value, lower case; None for ``null`` or nonsense."""
    parts = urlsplit(origin.strip())
    if parts.scheme not in ("http", "https") or not parts.netloc:
        return None
    return parts.netloc.lower()


class SecurityGuard:
    """ASGI middleware: host check, cross-site write check, body limits and security headers
    (see the module docstring)."""

    def __init__(
        self,
        app: ASGIApp,
        *,
        allowed_hosts: frozenset[str] | None,
        allowed_origins: Iterable[str] = (),
        max_body_bytes: int,
        route_body_bytes: Mapping[str, tuple[int, str]] | None = None,
        csp: str,
    ) -> None:
        self.app = app
        self.allowed_hosts = allowed_hosts
        self.allowed_origins = frozenset(
            a for a in (_origin_authority(o) for o in allowed_origins) if a is not None
        )
        self.max_body_bytes = max_body_bytes
        self.route_body_bytes = dict(route_body_bytes or {})
        self.headers = [
            (b"content-security-policy", csp.encode()),
            (b"x-frame-options", b"DENY"),
            (b"x-content-type-options", b"nosniff"),
            (b"referrer-policy", b"no-referrer"),
        ]
        self.header_names = frozenset(name for name, _ in self.headers)
        self._served_hosts: dict[bytes, bool] = {}

    async def __call__(self, scope: Scope, receive: Receive, send: Send) -> None:
        if scope["type"] != "http":
            await self.app(scope, receive, send)
            return
        headers = dict(reversed(scope["headers"]))  # the first value of each name wins
        refusal = self._refusal(scope, headers)
        if refusal is not None:
            status, kind, detail = refusal
            log.warning("refused %s %s: %s", scope["method"], scope["path"], detail)
            await self._reply(send, status, kind, detail)
            return
        limit, setting = self.route_body_bytes.get(
            scope["path"], (self.max_body_bytes, "max_body_bytes")
        )
        declared = headers.get(b"content-length", b"")
        if declared.isdigit() and int(declared) > limit:
            await self._reply(
                send, 413, "BodyTooLargeError", str(BodyTooLargeError(limit, setting).detail)
            )
            return
        started = False

        async def send_with_headers(message: Message) -> None:
            nonlocal started
            if message["type"] == "http.response.start":
                started = True
                given = message.get("headers", ())
                extra = self.headers
                for name, _ in given:  # a loop, not any(): every answer passes here
                    if name.lower() in self.header_names:  # the app set some itself: they stay
                        present = {name.lower() for name, _ in given}
                        extra = [(n, v) for n, v in self.headers if n not in present]
                        break
                message = {**message, "headers": [*given, *extra]}
            await send(message)

        try:
            if declared in (b"", b"0") and b"transfer-encoding" not in headers:
                await self.app(scope, receive, send_with_headers)  # no body to limit or check
            elif finite_json.is_json(headers.get(b"content-type")):
                await self._json_body(scope, receive, send_with_headers, limit, setting)
            else:
                await self.app(scope, _limited(receive, limit, setting), send_with_headers)
        except BodyTooLargeError as error:
            if started:
                raise
            await self._reply(send, error.status_code, type(error).__name__, str(error.detail))
        except ClientDisconnect:
            if started:
                raise
            # a client that left (or stalled: api/header_timeout.py) has nobody to answer
            log.info(
                "%s %s: the client left before its body was complete",
                scope["method"],
                scope["path"],
            )

    async def _json_body(
        self, scope: Scope, receive: Receive, send: Send, limit: int, setting: str
    ) -> None:
        """Read a JSON body whole, refuse it with 422 if it holds a number that is not finite
        (:mod:`api.finite_json`), else hand it to the app in one message.

        Raises :class:`BodyTooLargeError` once the bytes received pass ``limit``."""
        message = await receive()
        if message["type"] == "http.request" and message.get("more_body", False):
            chunks = [message.get("body", b"")]
            received = len(chunks[0])
            while message["type"] == "http.request" and message.get("more_body", False):
                message = await receive()
                chunks.append(message.get("body", b""))
                received += len(chunks[-1])
                if received > limit:
                    raise BodyTooLargeError(limit, setting)
            if message["type"] == "http.request":
                message = {"type": "http.request", "body": b"".join(chunks), "more_body": False}
        if message["type"] == "http.request":
            body = message.get("body", b"")
            if len(body) > limit:
                raise BodyTooLargeError(limit, setting)
            errors = finite_json.non_finite_errors(body)
            if errors:
                await finite_json.reply(send, errors)
                return
        pending: Message | None = message  # a client that left: the app reads that it did

        async def replay() -> Message:
            nonlocal pending
            if pending is None:
                return await receive()
            given, pending = pending, None
            return given

        await self.app(scope, replay, send)

    def _refusal(self, scope: Scope, headers: Mapping[bytes, bytes]) -> tuple[int, str, str] | None:
        """(status, error name, message) if the request must be refused, else None."""
        raw_host = headers.get(b"host", b"")
        host = raw_host.decode("latin-1")
        if raw_host and not self._serves(raw_host):
            return (
                400,
                "UntrustedHostError",
                f"Host: {host!r} is not a name of this server (allowed_hosts)",
            )
        if scope["method"] in SAFE_METHODS:
            return None
        origin = headers.get(b"origin")
        if origin is not None:
            authority = _origin_authority(origin.decode("latin-1"))
            if authority is not None and (
                authority == host.strip().lower() or authority in self.allowed_origins
            ):
                return None
            return (
                403,
                "CrossSiteRequestError",
                f"Origin: {origin.decode('latin-1')!r} may not write here: only this server's "
                "own pages and allowed_origins may",
            )
        site = headers.get(b"sec-fetch-site", b"").lower()
        if site in (b"cross-site", b"same-site"):
            return (
                403,
                "CrossSiteRequestError",
                f"Sec-Fetch-Site: {site.decode('latin-1')!r}: a request from another site may "
                "not write here",
            )
        return None

    def _serves(self, raw_host: bytes) -> bool:
        """True if the ``Host`` header value ``raw_host`` names this server. The verdicts for
        the first few names served are kept, as every request asks again."""
        if self.allowed_hosts is None or self._served_hosts.get(raw_host, False):
            return True
        served = _host_of(raw_host.decode("latin-1")) in self.allowed_hosts
        if served and len(self._served_hosts) < _SERVED_HOSTS_KEPT:
            self._served_hosts[raw_host] = True
        return served

    async def _reply(self, send: Send, status: int, kind: str, detail: str) -> None:
        body = json.dumps({"detail": detail, "error": kind}).encode()
        headers: list[tuple[bytes, bytes]] = [
            (b"content-type", b"application/json"),
            (b"content-length", str(len(body)).encode()),
            (b"connection", b"close"),
            *self.headers,
        ]
        await send({"type": "http.response.start", "status": status, "headers": headers})
        await send({"type": "http.response.body", "body": body})


def _limited(receive: Receive, limit: int, setting: str) -> Receive:
    """``receive``, raising :class:`BodyTooLargeError` once the body received passes ``limit``."""
    received = 0

    async def limited_receive() -> Message:
        nonlocal received
        message = await receive()
        if message["type"] == "http.request":
            received += len(message.get("body", b""))
            if received > limit:
                raise BodyTooLargeError(limit, setting)
        return message

    return limited_receive


@asynccontextmanager
async def saved_body(request: Request, directory: Path) -> AsyncIterator[Path]:
    """The request body, streamed into a new file in ``directory`` (the guard's body limit and
    timeout apply while it arrives); the file is removed when the context ends.

    The event loop writes each part as it comes (at most a socket buffer's worth); memory use
    stays at one part whatever the body's size.
    """
    directory.mkdir(parents=True, exist_ok=True)
    descriptor, name = tempfile.mkstemp(prefix="body-", dir=directory)
    path = Path(name)
    try:
        with os.fdopen(descriptor, "wb") as file:
            async for chunk in request.stream():
                file.write(chunk)
        yield path
    finally:
        path.unlink(missing_ok=True)


def armor_file_access(settings: Settings) -> FileAccess:
    """Where the server's ARMOR file commands may go: the data directory and
    ``armor_file_dirs``; LOAD WEB only under ``armor_url_prefixes``."""
    directories = [Path(d) for d in settings.armor_file_dirs.split(os.pathsep) if d.strip()]
    prefixes = [p.strip() for p in settings.armor_url_prefixes.split(",") if p.strip()]
    return FileAccess.confined(settings.data_dir, directories, prefixes)


def install(app: FastAPI, settings: Settings) -> None:
    """Put :class:`SecurityGuard` outside every other user middleware of ``app`` (call last,
    before the app first serves). Bag uploads have their own limit, ``max_upload_bytes``."""
    routes = {"/episodes/import/upload": (settings.max_upload_bytes, "max_upload_bytes")}
    options: dict[str, Any] = {
        "allowed_hosts": allowed_host_names(settings),
        "allowed_origins": [o for o in settings.allowed_origins.split(",") if o.strip()],
        "max_body_bytes": settings.max_body_bytes,
        "route_body_bytes": routes,
        "csp": content_security_policy(),
    }
    app.add_middleware(SecurityGuard, **options)
