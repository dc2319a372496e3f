"""What every ``engram`` command shares: the options that name a memory, opening it through the
composition root, and talking to the server that holds it.

A command names its memory by ``--data DIR`` (default ``$ENGRAM_DATA_DIR``, else
``~/.local/share/engram``) or ``--server URL``. It prints which memory it used on stderr, so
that its standard output stays what it promises (JSON, say). When the data directory's store is
held by a running server (``engram serve`` announces itself in the directory), the commands
that can talk to the server do so, and say so; ``--server`` asks a server explicitly.

Exit codes: 0 done; 1 not found, refused by the memory, or the memory cannot be reached;
2 bad input (an option, a file, a value).
"""

import json
import sys
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import TYPE_CHECKING, Annotated, Any, NoReturn

import typer
from pydantic import ValidationError

from api.config import Settings

if TYPE_CHECKING:
    import httpx

    from api.services import Services

__all__ = [
    "DataOption",
    "InitOption",
    "ServerOption",
    "TokenOption",
    "answer",
    "call",
    "fail",
    "memory_at",
    "opened",
    "reach",
    "remote",
    "settings_for",
    "tell",
]

DataOption = Annotated[
    Path | None,
    typer.Option(
        "--data",
        help="Data directory of the memory (default: $ENGRAM_DATA_DIR, else "
        "~/.local/share/engram).",
        show_default=False,
    ),
]
ServerOption = Annotated[
    str | None,
    typer.Option(
        help="An Engram server's URL to talk to instead of opening the data directory "
        "(default: the server that holds the data directory, if one runs).",
        show_default=False,
    ),
]
InitOption = Annotated[
    bool, typer.Option("--init", help="Create an empty memory if the directory has none.")
]
TokenOption = Annotated[
    str | None, typer.Option(envvar="ENGRAM_TOKEN", help="Bearer token for the server's writes.")
]


def tell(message: str) -> None:
    """A line for the person at the terminal, on stderr."""
    print(message, file=sys.stderr, flush=True)


def fail(message: str, code: int = 1) -> NoReturn:
    """Print ``error: message`` on stderr and exit with ``code``."""
    tell(f"error: {message}")
    raise typer.Exit(code)


def settings_for(data: Path | None = None, **overrides: Any) -> Settings:
    """The settings from the environment, with the options given on the command line."""
    given = {key: value for key, value in overrides.items() if value is not None}
    if data is not None:
        given["data_dir"] = data
    try:
        return Settings(**given)
    except ValidationError as error:
        problems = "; ".join(
            f"{'.'.join(str(p) for p in e['loc']) or 'setting'}: got {e.get('input')!r}, "
            f"{e['msg'].lower()}"
            for e in error.errors()
        )
        fail(f"invalid setting: {problems}", 2)


def memory_at(settings: Settings) -> str:
    """The memory a command opens, in words."""
    if settings.store_url is not None:
        return f"memory {settings.memory} at {settings.store_url}"
    return str(settings.data_dir)


def _open(settings: Settings, *, create: bool = False) -> "Services":
    """The memory ``settings`` name, opened here; a store held by another process raises
    StoreBusyError, anything else that stops it exits 1 with the reason."""
    from api.services import StoreBusyError, open_services
    from kg import EngramError

    try:
        services = open_services(settings, create=create)
    except StoreBusyError:
        raise
    except (EngramError, ValueError) as error:
        fail(str(error), 1)
    tell(f"memory: {services.where}")
    return services


@contextmanager
def opened(settings: Settings, *, create: bool = False) -> Iterator["Services"]:
    """The memory ``settings`` name, opened through the composition root for one command, and
    closed after it; exits 1 with the reason if it cannot be opened."""
    from api.services import StoreBusyError

    try:
        services = _open(settings, create=create)
    except StoreBusyError as error:
        fail(str(error), 1)
    with services:
        yield services


@contextmanager
def reach(
    settings: Settings, server: str | None, token: str | None = None
) -> Iterator["Services | httpx.Client"]:
    """The memory a command works on: an HTTP client of ``server`` if given; else the data
    directory opened here; else, when a running server holds the directory, a client of that
    server. Exits 1 with the reason when none can be had."""
    from api.services import StoreBusyError

    if server is None:
        try:
            services = _open(settings)
        except StoreBusyError as error:
            if error.server is None:
                fail(f"{error}; or give --server URL", 1)
            server = error.server
        else:
            with services:
                yield services
            return
    with remote(server.rstrip("/"), token) as client:
        yield client


@contextmanager
def remote(url: str, token: str | None = None, *, timeout: float = 120) -> Iterator["httpx.Client"]:
    """An HTTP client of the server at ``url``; says which server on stderr."""
    import httpx

    headers = {"Authorization": f"Bearer {token}"} if token else {}
    tell(f"memory: the Engram server at {url}")
    with httpx.Client(base_url=url, headers=headers, timeout=timeout) as client:
        yield client


def answer(response: "httpx.Response") -> Any:
    """The JSON body of a successful answer; otherwise exit with the server's reason (2 for
    the request's fault, 1 for the rest)."""
    if response.is_success:
        if not response.content:
            return None
        return (
            response.json()
            if "json" in response.headers.get("content-type", "")
            else (response.content)
        )
    try:
        detail = response.json().get("detail", response.text)
    except ValueError:
        detail = response.text
    if not isinstance(detail, str):
        detail = json.dumps(detail)
    fail(f"{response.status_code}: {detail}", 2 if response.status_code in (400, 413, 422) else 1)


def call(client: "httpx.Client", method: str, path: str, **kwargs: Any) -> Any:
    """``method path`` on the server; see :func:`answer`."""
    import httpx

    try:
        response = client.request(method, path, **kwargs)
    except httpx.HTTPError as error:
        fail(f"cannot reach {client.base_url}: {error}", 1)
    return answer(response)
