"""A real ROS master and ``engram ros`` / ``engram serve --ros`` as child processes.

Used by tests/ros and bench/ros.py. ROS's Python modules come from Debian's packages
(:func:`api.ros.system.load_ros`).
"""

import contextlib
import os
import signal
import subprocess
import sys
import time
import xmlrpc.client
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from api.ros.system import load_ros
from tests.conftest import free_port

load_ros()


ROOT = Path(__file__).resolve().parents[2]
ENGRAM = "from api.cli import app; app()"


def ros_env(master_uri: str, home: Path) -> dict[str, str]:
    """The environment of a child: this checkout first on the path, the master, logs in home."""
    env = dict(os.environ)
    env["PYTHONPATH"] = os.pathsep.join(p for p in (str(ROOT), env.get("PYTHONPATH")) if p)
    env["ROS_MASTER_URI"] = master_uri
    env["ROS_HOME"] = str(home)
    env["ROS_LOG_DIR"] = str(home / "log")
    env["ROS_HOSTNAME"] = "127.0.0.1"
    return env


@dataclass
class Master:
    """A ``rosmaster --core`` on a loopback port."""

    port: int
    home: Path
    process: subprocess.Popen[bytes] | None = None

    @property
    def uri(self) -> str:
        return f"http://127.0.0.1:{self.port}/"

    def start(self) -> "Master":
        self.process = subprocess.Popen(
            ["rosmaster", "--core", "-p", str(self.port)],
            env=ros_env(self.uri, self.home),
            stdout=subprocess.DEVNULL,
            stderr=subprocess.DEVNULL,
        )
        wait_for(lambda: master_call(self.uri, "getPid")[0] == 1, "the ROS master to start")
        return self

    def stop(self) -> None:
        if self.process is not None:
            stop_process(self.process)
            self.process = None


def wait_for(condition: Any, what: str, timeout_s: float = 60.0) -> None:
    deadline = time.monotonic() + timeout_s
    while True:
        try:
            if condition():
                return
        except OSError:  # not listening yet
            pass
        if time.monotonic() > deadline:
            raise TimeoutError(f"waited {timeout_s} s for {what}")
        time.sleep(0.05)


def stop_process(process: subprocess.Popen[bytes], timeout_s: float = 20) -> None:
    """SIGINT (a clean stop), then SIGKILL if it does not end."""
    if process.poll() is None:
        process.send_signal(signal.SIGINT)
        try:
            process.wait(timeout_s)
        except subprocess.TimeoutExpired:
            process.kill()
            process.wait()


def master_call(master_uri: str, method: str, *args: Any) -> Any:
    """One call of the master's XML-RPC API, on a connection closed after it."""
    with xmlrpc.client.ServerProxy(master_uri) as proxy:
        return getattr(proxy, method)("/tests", *args)


def service_registered(master_uri: str, service: str) -> bool:
    return bool(master_call(master_uri, "lookupService", service)[0] == 1)


@contextlib.contextmanager
def master(home: Path) -> Iterator[Master]:
    running = Master(free_port(), home).start()
    try:
        yield running
    finally:
        running.stop()


class Engram:
    """``engram ARGUMENTS`` as a child process (started at once; :meth:`wait` for its services),
    with ``ENVIRONMENT`` added to its environment."""

    def __init__(
        self,
        arguments: list[str],
        master: Master,
        home: Path,
        environment: dict[str, str] | None = None,
    ) -> None:
        self.master, self.home = master, home
        self._interrupted = False
        self.log_path = home / "engram.log"
        self._log = self.log_path.open("wb")
        self.process = subprocess.Popen(
            [sys.executable, "-c", ENGRAM, *arguments],
            env=ros_env(master.uri, home) | (environment or {}),
            stdout=self._log,
            stderr=subprocess.STDOUT,
            cwd=home,
        )

    def wait(self) -> "Engram":
        """Return once its ARMOR service is registered; raise with its output if it ended."""

        def ready() -> bool:
            if self.process.poll() is not None:
                raise RuntimeError(self.log_path.read_text())
            return service_registered(self.master.uri, "/armor_interface_srv")

        wait_for(ready, "engram to register its services")
        return self

    def interrupt(self) -> None:
        """Send SIGINT, as Ctrl-C does (:meth:`stop` then waits for the end)."""
        if self.process.poll() is None and not self._interrupted:
            self._interrupted = True
            self.process.send_signal(signal.SIGINT)

    def stop(self) -> int:
        """Stop it with SIGINT, as Ctrl-C does (once: a second one would hurry uvicorn); its
        exit code."""
        self.interrupt()
        try:
            self.process.wait(30)
        except subprocess.TimeoutExpired:
            self.process.kill()
            self.process.wait()
        self._log.close()
        return self.process.returncode


@contextlib.contextmanager
def engram(arguments: list[str], master: Master, home: Path) -> Iterator[Engram]:
    """``engram ARGUMENTS`` as a child process, once its ARMOR service is registered."""
    running = Engram(arguments, master, home)
    try:
        yield running.wait()
    finally:
        running.stop()
