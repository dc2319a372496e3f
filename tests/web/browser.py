"""A real headless browser for the view tests: Debian's ``chromium-headless-shell`` driven by
Playwright over its own protocol, with no browser download (``executable_path`` names the system
binary). Software GL (SwiftShader) gives three.js its WebGL."""

import shutil
import time
from pathlib import Path
from typing import Any

__all__ = ["CHROMIUM_ARGS", "chromium_path", "until"]

CANDIDATES = (
    "/usr/lib/chromium/chromium-headless-shell",
    "/usr/bin/chromium-headless-shell",
)

CHROMIUM_ARGS = [
    "--no-sandbox",
    "--disable-gpu-sandbox",
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-default-apps",
    "--disable-domain-reliability",
    "--disable-sync",
    "--no-first-run",
    "--no-default-browser-check",
    "--metrics-recording-only",
    "--use-angle=swiftshader",
    "--enable-unsafe-swiftshader",
]


def chromium_path() -> Path | None:
    """The system's headless Chromium, or None when the Debian package is not installed."""
    for candidate in CANDIDATES:
        if Path(candidate).is_file():
            return Path(candidate)
    found = shutil.which("chromium-headless-shell")
    return Path(found) if found else None


def until(page: Any, predicate: str, timeout_s: float = 30) -> None:
    """Wait until ``predicate`` (a JavaScript function) is true, polled from here: Playwright's
    wait_for_function compiles its text in the page, which the pages' Content-Security-Policy
    forbids (no 'unsafe-eval'), as it should."""
    deadline = time.monotonic() + timeout_s
    while not page.evaluate(predicate):
        assert time.monotonic() < deadline, f"never true: {predicate}"
        page.wait_for_timeout(50)
