"""A pytest plugin that names the sockets still open when the session ends, and where each was
made: ``PYTHONTRACEMALLOC=25 .venv/bin/pytest -p tests.open_sockets``.

A socket still referenced when the interpreter exits is reported only then, after pytest's
summary, as an "unclosed socket" ResourceWarning that does not say where it came from; this
lists them at the session's end instead, each with its allocation traceback when tracemalloc
traces (``PYTHONTRACEMALLOC``). Not loaded unless asked for.
"""

import gc
import socket
import tracemalloc

import pytest


def open_sockets() -> list[socket.socket]:
    """The socket objects alive in this process whose descriptor is still open."""
    return [s for s in gc.get_objects() if isinstance(s, socket.socket) and s.fileno() != -1]


def pytest_terminal_summary(terminalreporter: pytest.TerminalReporter) -> None:
    found = open_sockets()
    terminalreporter.section(f"open sockets at the session's end: {len(found)}")
    for sock in found:
        terminalreporter.line(repr(sock))
        trace = tracemalloc.get_object_traceback(sock)
        lines = trace.format() if trace is not None else ["  (allocated before tracing began)"]
        terminalreporter.line("\n".join(lines))
