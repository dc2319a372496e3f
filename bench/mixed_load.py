"""Analysts beside writers: SPARQL readers, ARMOR writers and ``/health`` against one live server.

The server runs in its own process (``uvicorn`` on loopback, on-disk store in a temporary
directory), as in production. Clients are threads of this process, one keep-alive connection
each (``http.client``):

- ``--writers`` threads (default 8) each send single ``ADD IND CLASS`` directives, each its own
  transaction, to their own reference, as fast as they are answered;
- ``--readers`` threads (default 8) alternate a point query (one subject's label) and a join
  (individuals with their classes and the classes' labels, LIMIT 20) on ``/sparql``;
- one thread asks ``/health`` every 50 ms;
- in a third phase, ``--scene-writers`` threads (default 2; 0 skips the phase) each store random
  4-object scenes in the scene memory (one directive list a scene, as a perception client
  sends it), as fast as they are answered: every read then first writes the score view those
  scenes changed (``Transactions.settle_view``).

Phases of ``--seconds`` each (default 8): readers alone (the baseline, same run), readers with
the writers, readers with the scene writers. Printed per phase: reader median and p99 per query
kind, ``/health`` median and p99, the writers' median and their directives per second, and the
ratio of the loaded figures to the baseline. Targets (issue 15): point and join median
< 50 ms, p99 < 250 ms, ``/health`` < 20 ms with 8 writers and 8 readers.

``--breakdown`` first prints, in this process on an on-disk store, what bringing a query's view
of the store up to date costs each way (medians): a backup of the store and a fresh read-only
open of it (what every query paid when writers had committed since the last snapshot, before
the workers kept copies), against replaying 10 single-directive commits into a worker's copy
(what a query pays now), each followed by the point query.

Run from the repository root::

    .venv/bin/python bench/mixed_load.py
    .venv/bin/python bench/mixed_load.py --seconds 4 --writers 4 --readers 4
    .venv/bin/python bench/mixed_load.py --breakdown
"""

import argparse
import http.client
import json
import os
import random
import statistics
import sys
import tempfile
import threading
import time
from pathlib import Path
from urllib.parse import urlencode

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))
from api.client._memory import Primitive, primitive_directives  # noqa: E402
from bench.servers import ChildServer  # noqa: E402

SERVER = """
import sys, uvicorn
from api.config import Settings
from api.main import create_app
settings = Settings(data_dir=sys.argv[1], host="127.0.0.1", port=int(sys.argv[2]))
uvicorn.run(create_app(settings), host="127.0.0.1", port=int(sys.argv[2]), log_level="warning",
            access_log=False)
"""
POINT = (
    "SELECT ?label WHERE { <https://w3id.org/engram/ontology#Sphere> "
    "<http://www.w3.org/2000/01/rdf-schema#label> ?label }"
)
JOIN = (
    "SELECT ?i ?c ?label WHERE { ?i a ?c . ?c a <http://www.w3.org/2002/07/owl#Class> . "
    "OPTIONAL { ?c <http://www.w3.org/2000/01/rdf-schema#label> ?label } } LIMIT 20"
)


def _directive(
    ref: str, *args: str, command: str = "ADD", first: str = "IND", second: str = "CLASS"
) -> bytes:
    return json.dumps(
        {
            "armor_request": {
                "client_name": ref,
                "reference_name": ref,
                "command": command,
                "primary_command_spec": first,
                "secondary_command_spec": second,
                "args": list(args),
            }
        }
    ).encode()


class Timings:
    """Latencies per kind, collected by many threads."""

    def __init__(self) -> None:
        self.lock = threading.Lock()
        self.seconds: dict[str, list[float]] = {}
        self.failures: dict[str, int] = {}

    def add(self, kind: str, seconds: float, ok: bool) -> None:
        with self.lock:
            if ok:
                self.seconds.setdefault(kind, []).append(seconds)
            else:
                self.failures[kind] = self.failures.get(kind, 0) + 1


def _timed(
    connection: http.client.HTTPConnection,
    method: str,
    path: str,
    body: bytes | None,
    headers: dict[str, str],
) -> tuple[float, bool]:
    start = time.perf_counter()
    connection.request(method, path, body=body, headers=headers)
    response = connection.getresponse()
    response.read()
    return time.perf_counter() - start, response.status == 200


def _reader(port: int, stop: threading.Event, timings: Timings) -> None:
    connection = http.client.HTTPConnection("127.0.0.1", port, timeout=60)
    accept = {"Accept": "application/sparql-results+json"}
    queries = [
        ("point", "/sparql?" + urlencode({"query": POINT})),
        ("join", "/sparql?" + urlencode({"query": JOIN})),
    ]
    i = 0
    while not stop.is_set():
        kind, path = queries[i % 2]
        seconds, ok = _timed(connection, "GET", path, None, accept)
        timings.add(kind, seconds, ok)
        i += 1


def _writer(port: int, ref: str, stop: threading.Event, timings: Timings) -> None:
    connection = http.client.HTTPConnection("127.0.0.1", port, timeout=60)
    headers = {"Content-Type": "application/json"}
    connection.request(
        "POST",
        "/armor_interface_srv",
        body=_directive(
            ref,
            "",
            f"http://ex.org/{ref}",
            "false",
            "PELLET",
            "true",
            command="LOAD",
            first="FILE",
            second="",
        ),
        headers=headers,
    )
    connection.getresponse().read()
    i = 0
    while not stop.is_set():
        seconds, ok = _timed(
            connection,
            "POST",
            "/armor_interface_srv",
            _directive(ref, f"i{i}", f"C{i % 7}"),
            headers,
        )
        timings.add("write", seconds, ok)
        i += 1


def _scene_list(ref: str, rng: random.Random) -> bytes:
    """A directive list storing one random 4-object scene in the scene memory (as a perception
    client sends it: LOAD INIT, the primitives' ADDs, SCENE UPDATED)."""
    directives = [("LOAD", "INIT", "", [])]
    for k in range(4):
        kind = rng.choice(["Sphere", "Cylinder", "Cone", "Plane"])
        centre = (rng.uniform(0, 1), rng.uniform(0, 1), rng.uniform(0, 0.5))
        axis = None if kind == "Sphere" else rng.choice([(0.0, 0.0, 1.0), (1.0, 0.0, 0.0)])
        radius = 0.04 if kind == "Sphere" else None
        primitive = Primitive(f"o{k}", kind, centre, axis=axis, radius=radius)
        directives += primitive_directives(primitive)
    directives.append(("SCENE", "UPDATED", "", []))
    requests = [
        json.loads(_directive(ref, *args, command=c, first=f, second=s2))["armor_request"]
        for c, f, s2, args in directives
    ]
    return json.dumps({"armor_requests": requests}).encode()


def _scene_writer(port: int, ref: str, stop: threading.Event, timings: Timings) -> None:
    connection = http.client.HTTPConnection("127.0.0.1", port, timeout=60)
    headers = {"Content-Type": "application/json"}
    rng = random.Random(ref)
    while not stop.is_set():
        body = _scene_list(ref, rng)
        start = time.perf_counter()
        connection.request("POST", "/armor_interface_serialized_srv", body=body, headers=headers)
        answer = json.loads(connection.getresponse().read())
        ok = all(r["success"] for r in answer["armor_responses"])
        timings.add("scene", time.perf_counter() - start, ok)


def _health(port: int, stop: threading.Event, timings: Timings) -> None:
    connection = http.client.HTTPConnection("127.0.0.1", port, timeout=60)
    while not stop.is_set():
        seconds, ok = _timed(connection, "GET", "/health", None, {})
        timings.add("health", seconds, ok)
        time.sleep(0.05)


def phase(
    port: int, *, readers: int, writers: int, seconds: float, scene_writers: int = 0
) -> Timings:
    """Run the clients for ``seconds`` and return their latencies."""
    timings = Timings()
    stop = threading.Event()
    threads = [threading.Thread(target=_reader, args=(port, stop, timings)) for _ in range(readers)]
    threads += [
        threading.Thread(target=_writer, args=(port, f"w{n}_{time.monotonic_ns()}", stop, timings))
        for n in range(writers)
    ]
    threads += [
        threading.Thread(target=_scene_writer, args=(port, f"s{n}", stop, timings))
        for n in range(scene_writers)
    ]
    threads.append(threading.Thread(target=_health, args=(port, stop, timings)))
    for thread in threads:
        thread.start()
    time.sleep(seconds)
    stop.set()
    for thread in threads:
        thread.join()
    return timings


def _p99(values: list[float]) -> float:
    ordered = sorted(values)
    return ordered[min(len(ordered) - 1, int(0.99 * len(ordered)))]


def report(label: str, timings: Timings, seconds: float, baseline: Timings | None) -> None:
    print(f"{label}:")
    for kind in ("point", "join", "health", "write", "scene"):
        values = timings.seconds.get(kind, [])
        if not values:
            continue
        median, p99 = statistics.median(values), _p99(values)
        rate = len(values) / seconds
        line = (
            f"  {kind:6s} median {median * 1000:7.1f} ms  p99 {p99 * 1000:7.1f} ms  ({rate:6.0f}/s)"
        )
        base = baseline.seconds.get(kind) if baseline else None
        if base:
            ratio, ratio99 = median / statistics.median(base), p99 / _p99(base)
            line += f"  median {ratio:5.1f} x, p99 {ratio99:5.1f} x readers alone"
        failed = timings.failures.get(kind, 0)
        if failed:
            line += f"  [{failed} failed]"
        print(line)


def breakdown(runs: int = 20, commits: int = 10) -> None:
    """Print the cost of a fresh snapshot (backup + open) against a replay, each + a query."""
    import shutil
    import uuid

    import pyoxigraph

    sys.path.insert(0, str(ROOT))
    from kg import Store, ensure_ontology
    from ontologies.vocab import RDF_TYPE, RDFS_LABEL, engram

    def one_commit(store: Store, n: int) -> None:
        with store.transaction() as tx:
            tx.insert(engram(f"i{n}"), RDF_TYPE, engram(f"C{n % 7}"), engram("g"))
            tx.insert(engram(f"i{n}"), RDFS_LABEL, pyoxigraph.Literal(f"i{n}"), engram("g"))

    with tempfile.TemporaryDirectory() as data:
        store = Store(Path(data) / "store")
        ensure_ontology(store)
        for n in range(2000):
            one_commit(store, n)
        log = store.commit_log()
        fresh, replayed = [], []
        copy = Path(data) / "copy"
        store.backup(copy)
        worker_copy = pyoxigraph.Store(str(copy))
        for run in range(runs):
            generation = store.generation
            for n in range(commits):
                one_commit(store, 10_000 + run * commits + n)
            start = time.perf_counter()
            path = Path(data) / uuid.uuid4().hex
            store.backup(path)
            snapshot = pyoxigraph.Store.read_only(str(path))
            list(snapshot.query(POINT))
            fresh.append(time.perf_counter() - start)
            del snapshot
            shutil.rmtree(path)
            start = time.perf_counter()
            for commit in log.since(generation, store.generation) or []:
                if commit.inserts:
                    worker_copy.extend(commit.inserts)
                if commit.update:
                    worker_copy.update(commit.update)
            list(worker_copy.query(POINT))
            replayed.append(time.perf_counter() - start)
        one = os.getloadavg()[0]
        fresh_ms = statistics.median(fresh) * 1000
        replay_ms = statistics.median(replayed) * 1000
        print(
            f"breakdown ({len(store)} quads, load average {one:.2f}): backup + read-only open + "
            f"point query {fresh_ms:.1f} ms; replay of {commits} commits + point query "
            f"{replay_ms:.2f} ms ({fresh_ms / replay_ms:.0f} x less), medians of {runs}"
        )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--seconds", type=float, default=8.0, help="length of each phase")
    parser.add_argument("--readers", type=int, default=8)
    parser.add_argument("--writers", type=int, default=8)
    parser.add_argument(
        "--snapshot-max-age",
        default="0",
        help="ENGRAM_SPARQL_SNAPSHOT_MAX_AGE_S for the server (0: exact snapshots)",
    )
    parser.add_argument(
        "--scene-writers",
        type=int,
        default=2,
        help="clients storing scenes in the scene memory in a third phase (0: no such phase)",
    )
    parser.add_argument(
        "--breakdown", action="store_true", help="first time snapshot against replay in-process"
    )
    options = parser.parse_args()
    if options.breakdown:
        breakdown()
    one, five, fifteen = os.getloadavg()
    print(
        f"mixed load, {options.readers} readers, {options.writers} writers, "
        f"{options.seconds:g} s a phase, snapshot max age {options.snapshot_max_age} s "
        f"(load average {one:.2f} {five:.2f} {fifteen:.2f} on {os.cpu_count()} CPUs)"
    )
    with tempfile.TemporaryDirectory() as data:
        env = {"ENGRAM_SPARQL_SNAPSHOT_MAX_AGE_S": str(options.snapshot_max_age)}
        server = ChildServer(data, SERVER, env=env)
        try:
            alone = phase(server.port, readers=options.readers, writers=0, seconds=options.seconds)
            report("readers alone", alone, options.seconds, None)
            mixed = phase(
                server.port,
                readers=options.readers,
                writers=options.writers,
                seconds=options.seconds,
            )
            report("readers with writers", mixed, options.seconds, alone)
            if options.scene_writers:
                perceiving = phase(
                    server.port,
                    readers=options.readers,
                    writers=0,
                    seconds=options.seconds,
                    scene_writers=options.scene_writers,
                )
                report(
                    f"readers with {options.scene_writers} scene writers",
                    perceiving,
                    options.seconds,
                    alone,
                )
        finally:
            server.stop()


if __name__ == "__main__":
    main()
