"""A server the bench measures, in a child process of its own, as in production."""

import os
import subprocess
import sys
import time
from pathlib import Path

import httpx

from tests.conftest import free_port

ROOT = Path(__file__).resolve().parent.parent


class ChildServer:
    """The Python ``code`` (given the data directory and a free port as ``sys.argv[1:3]``)
    running in a child process with the checkout at ``root`` on its path and ``env`` added to
    its environment; returns once ``GET /health`` answers.

    Raises :class:`RuntimeError` if the server does not answer within 60 s or exits first.
    """

    def __init__(
        self, data: str, code: str, *, root: Path = ROOT, env: dict[str, str] | None = None
    ) -> None:
        self.port = free_port()
        self.url = f"http://127.0.0.1:{self.port}"
        environment = {**os.environ, "PYTHONPATH": str(root), **(env or {})}
        self.process = subprocess.Popen(
            [sys.executable, "-c", code, data, str(self.port)], cwd=root, env=environment
        )
        deadline = time.monotonic() + 60
        while True:
            try:
                httpx.get(self.url + "/health", timeout=1).raise_for_status()
                return
            except httpx.HTTPError:
                if time.monotonic() > deadline or self.process.poll() is not None:
                    self.stop()
                    raise RuntimeError("the bench server did not start") from None
                time.sleep(0.1)

    def stop(self) -> None:
        """End the server (SIGTERM) and wait for it."""
        self.process.terminate()
        self.process.wait(timeout=30)
