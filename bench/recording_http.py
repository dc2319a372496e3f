"""The iCub configuration of Table I ingested over HTTP from a separate client process.

The server (uvicorn on loopback, in this process) records; a child process (``spawn``) plays
the robot: the same 5 ms loop as ``bench/recording.py``, every due sample joining that loop's
tick, ticks sent as binary batches (``application/x-engram-batch``) every ``--batch-ms`` by a
sender thread, as a robot's bridge would, so the sensor loop never waits for a post (the
largest backlog of batches is printed: a server that cannot keep up makes it grow). At the
end the recording is closed over HTTP and its counts compared with the samples the sensors
produced: target 100 % stored, 0 dropped, the client never more than 100 ms behind.

    .venv/bin/python bench/recording_http.py --seconds 20
"""

from __future__ import annotations

import argparse
import math
import multiprocessing
import queue
import shutil
import tempfile
import threading
import time
from pathlib import Path
from typing import Any

import httpx
import numpy as np

LOOP_S = 0.005


def client_process(url: str, seconds: float, batch_ms: float, out: Any) -> None:
    """The robot: produce the iCub's samples in real time and post them in batches."""
    from bench.recording import ROBOTS, Source
    from episodes.streams.wire import BATCH_MEDIA_TYPE, encode_batch

    sensors = ROBOTS["icub"]
    rng = np.random.default_rng(7)
    sources = [Source(s, rng) for s in sensors]
    total = [math.ceil(seconds * s.hz - 1e-9) for s in sensors]
    sent = [0] * len(sensors)
    base = "/episodes/http-icub/streams"
    max_lag = 0.0
    batches: queue.Queue[bytes | None] = queue.Queue()
    backlog: dict[str, Any] = {"max": 0, "failure": ""}

    def sender(client: httpx.Client) -> None:
        """Posts the batches in order, so that the sensor loop never waits for the network."""
        while (body := batches.get()) is not None:
            backlog["max"] = max(backlog["max"], batches.qsize() + 1)
            try:
                client.post(
                    f"{base}/samples", content=body, headers={"content-type": BATCH_MEDIA_TYPE}
                ).raise_for_status()
            except httpx.HTTPError as error:
                backlog["failure"] = str(error)

    with httpx.Client(base_url=url, timeout=60) as client:
        for sensor in sensors:
            body = {"name": sensor.name, "kind": sensor.kind, **sensor.settings}
            client.post(f"{base}/providers", json=body).raise_for_status()
        posting = threading.Thread(target=sender, args=(client,))
        posting.start()
        start = time.monotonic()
        wall0 = time.time_ns()
        pending_ticks: list[dict[str, Any]] = []
        last_post = start
        while True:
            now = time.monotonic()
            samples: dict[str, Any] = {}
            for k, source in enumerate(sources):
                due = start + sent[k] / source.sensor.hz
                if sent[k] < total[k] and due <= now:
                    samples[source.sensor.name] = source.next()
                    max_lag = max(max_lag, now - due)
                    sent[k] += 1
            if samples:
                tick_ns = wall0 + int((now - start) * 1e9)
                pending_ticks.append({"time_ns": tick_ns, "samples": samples})
            remaining = [
                start + sent[k] / s.hz for k, s in enumerate(sensors) if sent[k] < total[k]
            ]
            if pending_ticks and (not remaining or now - last_post >= batch_ms / 1000):
                batches.put(encode_batch(pending_ticks))
                pending_ticks = []
                last_post = time.monotonic()
            if not remaining:
                break
            wait = min(min(remaining) - time.monotonic(), LOOP_S)
            if wait > 0:
                time.sleep(wait)
        batches.put(None)
        posting.join()
    out.put(
        {
            "sent": dict(zip([s.name for s in sensors], sent, strict=True)),
            "lag": max_lag,
            "backlog": backlog["max"],
            "failure": backlog["failure"],
        }
    )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--seconds", type=float, default=20.0)
    parser.add_argument("--batch-ms", type=float, default=20.0)
    args = parser.parse_args()

    import uvicorn

    from api.config import Settings
    from api.main import create_app
    from bench.recording import ROBOTS
    from tests.conftest import free_port

    data = Path(tempfile.mkdtemp(prefix="engram-bench-http-"))
    port = free_port()
    settings = Settings(host="127.0.0.1", port=port, data_dir=data)
    server = uvicorn.Server(
        uvicorn.Config(
            create_app(settings), host=settings.host, port=settings.port, log_level="warning"
        )
    )
    thread = threading.Thread(target=server.run, daemon=True)
    thread.start()
    while not server.started:
        time.sleep(0.05)
    url = f"http://{settings.host}:{settings.port}"
    with httpx.Client(base_url=url, timeout=120) as http:
        http.post("/episodes", json={"activity": "babbling", "id": "http-icub"}).raise_for_status()
        http.post("/episodes/http-icub/streams").raise_for_status()
        context = multiprocessing.get_context("spawn")
        queue = context.Queue()
        child = context.Process(
            target=client_process, args=(url, args.seconds, args.batch_ms, queue)
        )
        wall0 = time.monotonic()
        child.start()
        result = queue.get()
        child.join()
        wall = time.monotonic() - wall0
        closed = http.post("/episodes/http-icub/streams/close").json()
    server.should_exit = True
    thread.join(timeout=30)
    shutil.rmtree(data, ignore_errors=True)
    expected = {s.name: math.ceil(args.seconds * s.hz - 1e-9) for s in ROBOTS["icub"]}
    print(
        f"iCub over HTTP from a separate process: {args.seconds:g} s, "
        f"batches every {args.batch_ms:g} ms"
    )
    print(
        f"{'provider':22} {'expected':>8} {'sent':>8} {'stored':>8} {'stored %':>8} {'dropped':>7}"
    )
    worst = 100.0
    dropped_total = 0
    for channel in closed["channels"]:
        name = channel["provider"]
        stored = channel["count_stored"]
        dropped = channel["count_dropped"]
        dropped_total += dropped
        share = 100.0 * stored / expected[name]
        worst = min(worst, share)
        print(
            f"{name:22} {expected[name]:>8} {result['sent'][name]:>8} {stored:>8} "
            f"{share:>7.1f}% {dropped:>7}"
        )
    lag_ms = 1000 * result["lag"]
    print(
        f"client late by at most {lag_ms:.1f} ms; wall {wall:.1f} s for {args.seconds:g} s of data"
        f" (client start included); at most {result['backlog']} batches "
        f"({result['backlog'] * args.batch_ms:g} ms of data) waiting to be posted"
    )
    if result["failure"]:
        print(f"a post failed: {result['failure']}")
    met = worst >= 100.0 and dropped_total == 0 and lag_ms < 100 and not result["failure"]
    print(f"target (100 % stored, 0 dropped, < 100 ms late): {'met' if met else 'NOT met'}")


if __name__ == "__main__":
    main()
