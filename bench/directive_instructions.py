"""Instructions a simple ARMOR directive costs the server, counted by callgrind: repeatable
however loaded the machine is, where times are not.

A child process builds the app (``api.main.create_app``, on-disk store in a temporary
directory), runs its lifespan and sends it N directive requests through its ASGI callable, with
the headers and body a client sends (``ADD IND CLASS`` and ``QUERY IND`` alternating, as
``bench/directives.py``): everything the app does for a request (the middleware stack, the
guard, routing, reading, the engine, the answer), not the socket or uvicorn's parsing. The child
runs under ``valgrind --tool=callgrind`` twice, with N and 2N requests, counting instructions
only while it sends them (``--instr-atstart=no``, then ``callgrind_control -i on`` from the child
itself: start-up and warm-up run uninstrumented, several times faster); the difference divided by
N is the count per request, the switching's own cost cancelled out.

``--server`` counts the whole server process instead: ``engram serve``'s uvicorn set-up (the
server of ``bench/directives.py``) under callgrind, instrumented only while one keep-alive
client of this process sends N directives (after a warm-up of 200): uvicorn's parsing, its
checks of the answer's headers and the connection's time limits included; count ÷ N. The
server's periodic upkeep is put off (``ENGRAM_SLEEP_CHECK_S``), since how often it runs within
the count depends on the machine's load; timers that remain (the connection's time limit) are
a few thousand instructions every ten seconds. Both checkouts are counted at the same time.

``--against DIR`` counts the checkout in ``DIR`` too (its code, this Python environment) and
prints the ratio. ``--null`` replaces the directive's work (reading the body into directives,
the engine, the answer) by a fixed answer, leaving the HTTP layers' own count.

Run from the repository root (each count takes a minute or two under valgrind)::

    .venv/bin/python bench/directive_instructions.py --against ../checkout-of-6b1d215
    .venv/bin/python bench/directive_instructions.py --null --against ../checkout-of-6b1d215
    .venv/bin/python bench/directive_instructions.py --server --against ../checkout-of-6b1d215
"""

import argparse
import http.client
import json
import os
import re
import signal
import subprocess
import sys
import tempfile
import time
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))
from bench.timing import load_average  # noqa: E402
from tests.conftest import free_port  # noqa: E402

CHILD = r"""
import asyncio, json, os, subprocess, sys, tempfile
from pathlib import Path
from api.config import Settings
from api.main import create_app

COUNT, NULL = int(sys.argv[1]), sys.argv[2] == "null"
if NULL:  # the directive's own work replaced by a fixed answer: the HTTP layers alone
    import api.routes.armor as routes
    async def fixed(*args, **kwargs):
        return b'{"armor_response":{"success":true}}'
    if hasattr(routes, "answer"):
        routes.answer = fixed
    else:  # a checkout from before api/directives.py
        routes.answer_single = fixed

def directive(i):
    if i % 2 == 0:
        command, second, args = "ADD", "CLASS", [f"c_{i}", f"Class_{i % 7}"]
    else:
        command, second, args = "QUERY", "", [f"c_{i - 1}"]
    request = {"client_name": "c", "reference_name": "bench", "command": command,
               "primary_command_spec": "IND", "secondary_command_spec": second, "args": args}
    return json.dumps({"armor_request": request}).encode()

async def post(app, body):
    scope = {"type": "http", "asgi": {"version": "3.0", "spec_version": "2.3"},
             "http_version": "1.1", "server": ("127.0.0.1", 8000), "client": ("127.0.0.1", 50000),
             "scheme": "http", "method": "POST", "root_path": "", "path": "/armor_interface_srv",
             "raw_path": b"/armor_interface_srv", "query_string": b"", "state": {},
             "headers": [(b"host", b"127.0.0.1:8000"), (b"accept-encoding", b"identity"),
                         (b"content-length", str(len(body)).encode()),
                         (b"content-type", b"application/json")]}
    messages = [{"type": "http.request", "body": body, "more_body": False}]
    sent = []
    async def receive():
        return messages.pop() if messages else {"type": "http.disconnect"}
    async def send(message):
        sent.append(message)
    await app(scope, receive, send)
    assert sent[0]["status"] == 200, sent

async def main():
    with tempfile.TemporaryDirectory() as data:
        app = create_app(Settings(data_dir=Path(data), host="127.0.0.1", port=8000))
        async with app.router.lifespan_context(app):
            load = {"armor_request": {"reference_name": "bench", "command": "LOAD",
                    "primary_command_spec": "FILE", "args": ["", "http://ex.org/bench", "false",
                    "PELLET", "True"]}}
            await post(app, json.dumps(load).encode())
            for i in range(200):  # warm-up: every model built, every path taken once
                await post(app, directive(10**6 + i))
            instrument("on")
            for i in range(COUNT):
                await post(app, directive(i))
            instrument("off")

def instrument(state):
    subprocess.run(["callgrind_control", "-i", state, str(os.getpid())], check=True,
                   capture_output=True)

asyncio.run(main())
"""


def instructions(root: Path, count: int, null: bool) -> int:
    """Instructions of one child run over the checkout at ``root``."""
    with tempfile.TemporaryDirectory(prefix="engram-callgrind-") as work:
        out = Path(work) / "callgrind.out"
        env = {**os.environ, "PYTHONPATH": str(root)}
        subprocess.run(
            [
                "valgrind",
                "--tool=callgrind",
                "--instr-atstart=no",
                f"--callgrind-out-file={out}",
                sys.executable,
                "-c",
                CHILD,
                str(count),
                "null" if null else "work",
            ],
            cwd=root,
            env=env,
            check=True,
            capture_output=True,
        )
        totals = re.search(r"^totals: (\d+)", out.read_text(), re.MULTILINE)
        if totals is None:
            raise RuntimeError(f"no totals line in {out}")
        return int(totals.group(1))


def per_request(root: Path, count: int, null: bool) -> float:
    """Instructions per request: (2N run - N run) / N, the two runs side by side."""
    with ThreadPoolExecutor(2) as pool:
        once, twice = pool.map(lambda n: instructions(root, n, null), (count, 2 * count))
    return (twice - once) / count


def _body(i: int) -> str:
    """The ``i``-th directive's body, as the child's ``directive(i)`` writes it."""
    if i % 2 == 0:
        command, second, args = "ADD", "CLASS", [f"s_{i}", f"Class_{i % 7}"]
    else:
        command, second, args = "QUERY", "", [f"s_{i - 1}"]
    request = {
        "client_name": "c",
        "reference_name": "bench",
        "command": command,
        "primary_command_spec": "IND",
        "secondary_command_spec": second,
        "args": args,
    }
    return json.dumps({"armor_request": request})


def server_per_request(root: Path, count: int) -> float:
    """Instructions of the server process per directive, counted while ``count`` are sent."""
    sys.path.insert(0, str(ROOT / "bench"))
    from directives import SERVER

    with tempfile.TemporaryDirectory(prefix="engram-callgrind-") as work:
        out = Path(work) / "callgrind.out"
        port = free_port()
        command = ["valgrind", "--tool=callgrind", "--instr-atstart=no"]
        command += [f"--callgrind-out-file={out}", sys.executable, "-c", SERVER, work, str(port)]
        # the upkeep every sleep_check_s (a store flush...) would be counted by wall time
        env = {**os.environ, "PYTHONPATH": str(root), "ENGRAM_SLEEP_CHECK_S": "86400"}
        server = subprocess.Popen(
            command, cwd=root, env=env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL
        )
        try:
            connection = _connect(port, server)

            def post(body: str) -> None:
                connection.request(
                    "POST", "/armor_interface_srv", body, {"Content-Type": "application/json"}
                )
                response = connection.getresponse()
                text = response.read()
                if response.status != 200 or not json.loads(text)["armor_response"]["success"]:
                    raise RuntimeError(f"a directive failed: {text!r}")

            load = {"armor_request": {"reference_name": "bench", "command": "LOAD",
                    "primary_command_spec": "FILE", "args": ["", "http://ex.org/bench", "false",
                    "PELLET", "True"]}}  # fmt: skip
            post(json.dumps(load))
            for i in range(200):
                post(_body(10**6 + i))
            _instrument(server.pid, "on")
            for i in range(count):
                post(_body(i))
            _instrument(server.pid, "off")
            connection.close()
        finally:
            server.send_signal(signal.SIGINT)
            server.wait(timeout=600)
        totals = re.search(r"^totals: (\d+)", out.read_text(), re.MULTILINE)
        if totals is None:
            raise RuntimeError(f"no totals line in {out}")
        return int(totals.group(1)) / count


def _connect(port: int, server: subprocess.Popen[bytes]) -> http.client.HTTPConnection:
    """A connection to the server once it answers ``/health`` (minutes under valgrind)."""
    deadline = time.monotonic() + 900
    while True:
        try:
            connection = http.client.HTTPConnection("127.0.0.1", port, timeout=600)
            connection.request("GET", "/health")
            response = connection.getresponse()
            response.read()
            if response.status == 200:
                return connection
        except OSError:
            pass
        if time.monotonic() > deadline or server.poll() is not None:
            raise RuntimeError("the server did not start under valgrind")
        time.sleep(1)


def _instrument(pid: int, state: str) -> None:
    subprocess.run(["callgrind_control", "-i", state, str(pid)], check=True, capture_output=True)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--against", type=Path, metavar="CHECKOUT", help="count it too")
    parser.add_argument("--requests", type=int, default=1000, help="N (default 1000)")
    parser.add_argument("--null", action="store_true", help="the HTTP layers alone")
    parser.add_argument("--server", action="store_true", help="the whole server process")
    options = parser.parse_args()
    if options.server:
        print("# ARMOR simple directive over HTTP, callgrind: the whole server process")
    else:
        what = "HTTP layers alone (fixed answer)" if options.null else "whole directive"
        print(f"# ARMOR simple directive, in-process ASGI, callgrind: {what}")
    print(f"  {load_average()}")

    def count(root: Path) -> float:
        if options.server:
            return server_per_request(root, options.requests)
        return per_request(root, options.requests, options.null)

    if options.server and options.against is not None:  # side by side, under the same load
        with ThreadPoolExecutor(2) as pool:
            this, other = pool.map(count, (ROOT, options.against.resolve()))
    else:
        this = count(ROOT)
    print(f"  this checkout: {this / 1000:.0f}k instructions a request")
    if options.against is not None:
        if not options.server:
            other = count(options.against.resolve())
        print(f"  {options.against}: {other / 1000:.0f}k instructions a request")
        print(f"  this ÷ other: {this / other:.2f}")
    print(f"  {load_average()}")


if __name__ == "__main__":
    main()
