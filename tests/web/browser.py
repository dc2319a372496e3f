"""A real headless browser for the view tests: Debian's ``chromium-headless-shell`` driven by
Playwright over its own protocol, with no browser download (``executable_path`` names the system
binary). Software GL (SwiftShader) gives three.js its WebGL."""

import shutil
from pathlib import Path

__all__ = ["CHROMIUM_ARGS", "chromium_path"]

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
