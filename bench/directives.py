"""ARMOR directives over HTTP on loopback: directives per second, and REASON against owlrl.

**Throughput.** The server runs in its own process (``uvicorn``, on-disk store in a temporary
directory), as in production; clients are threads of this process, each with one keep-alive
connection. A "simple directive" alternates ``ADD IND CLASS`` and ``QUERY IND`` on a reference
with buffered reasoning (the RDS tutorial's advice), each directive its own request and
transaction. Baselines in the same run: ``GET /health`` (HTTP with no work) and the same
directives on an in-process ``ArmorEngine`` (no HTTP). Target: at least 3,000 simple
directives/s with 8 clients. The clients are threads of one process (``http.client``, about
40 µs of client work a request): the bare endpoint's rate shows they are not what limits the
server's. Since the machine may be shared, the server process's CPU time per request (from
``/proc``) is printed too, for the directives and for the bare endpoint: it moves much less
with the other load than the rates do.

**Against another checkout** (``--against DIR``): the same 8 clients against this checkout's
server and the server of the checkout in ``DIR`` (its code, on the same Python environment), in
turns, so that both see the same machine load; prints each run and the ratios of the medians of
the rates and of the server CPU per request. ``--floors`` adds, in the same turns, what the HTTP
stack alone costs a request like a directive's: a FastAPI route reading the body and answering a
fixed body under the same uvicorn, and a plain ASGI app doing the same under uvicorn alone.

**REASON.** On the synthetic scene ontologies of ``reasoners.owl_rl.synthetic`` (about 10k and
50k triples), loaded with LOAD FILE into an engine on an on-disk store:

1. a full REASON directive through the engine (reading the reference, the closure, and the one
   all-or-nothing write of every inferred triple, bulk loaded by ``kg.Store.fill_graph``),
   against owlrl 7.6.2's
   ``DeductiveClosure(OWLRL_Semantics).expand()`` on an rdflib graph of the same triples (parse
   not timed); owlrl at 50k only with ``--owlrl-50k`` (about 100 s). The ratio is owlrl ÷ the
   median of the REASONs run just before and after owlrl, in the same process. Identity: the
   inferred graph against owlrl's additions, owlrl's out-of-scope output filtered as
   ``tests/reasoners/owl_rl/conftest.py`` documents;
2. on the 50k reference: the time of a REASON after 5 new assertions (a new object: type,
   scene, score, level, a relation), sent as 5 ADD directives beforehand (buffered reasoner),
   and the time of one list ``[5 ADDs, REASON]``, through the engine and over HTTP; then the
   inferred graph is compared with a full REASON of the same asserted graph. Target < 50 ms.

**Long lists.** One directive list of N ``ADD IND CLASS`` directives (distinct individuals) to a
fresh reference, sent as one request to the server process, for N = 1,000, 5,000 and 20,000;
printed with the time per directive relative to the 1,000-directive list, which is 1.0 for a
list whose cost is linear in its length (issue 12: 5,000 took 5 s and 20,000 took 105 s,
quadratic). Target: 20,000 in under 5 s.

Run from the repository root::

    .venv/bin/python bench/directives.py                 # everything, owlrl at 10k only
    .venv/bin/python bench/directives.py --owlrl-50k     # owlrl at 50k too (slow)
    .venv/bin/python bench/directives.py --only throughput --seconds 5
    .venv/bin/python bench/directives.py --only lists
    .venv/bin/python bench/directives.py --against ../other-checkout --seconds 3 --rounds 4
    .venv/bin/python bench/directives.py --against ../other-checkout --rounds 3 --floors
"""

import argparse
import http.client
import json
import os
import statistics
import sys
import tempfile
import threading
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

import httpx
import owlrl

from api.armor import ArmorEngine
from api.protocol import ArmorDirectiveReq
from kg import Store
from ontologies.vocab import reference_graph
from reasoners.owl_rl import materialise
from reasoners.owl_rl.synthetic import EX, scene_ontology

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
sys.path.insert(0, str(Path(__file__).parent))
from reasoning import owlrl_closure

from bench.servers import ChildServer
from bench.timing import load_average

ROOT = Path(__file__).resolve().parent.parent

SERVER = """
import sys, uvicorn
from api.config import Settings
from api.main import create_app
settings = Settings(data_dir=sys.argv[1], host="127.0.0.1", port=int(sys.argv[2]))
if hasattr(settings, "header_timeout_s"):  # engram serve's protocol, as the checkout has it
    from api.header_timeout import with_header_timeout
    try:
        http = with_header_timeout(
            settings.header_timeout_s, body_timeout_s=settings.body_timeout_s
        )
    except TypeError:
        http = with_header_timeout(settings.header_timeout_s)
else:
    http = "auto"
uvicorn.run(create_app(settings), host="127.0.0.1", port=int(sys.argv[2]), log_level="warning",
            access_log=False, http=http)
"""
BARE = """
import sys, uvicorn
from fastapi import FastAPI
app = FastAPI()
@app.get("/health")
async def bare() -> dict[str, str]:
    return {"status": "ok"}
uvicorn.run(app, host="127.0.0.1", port=int(sys.argv[2]), log_level="warning", access_log=False)
"""
"""A bare endpoint under the same uvicorn settings: the HTTP stack's ceiling for these clients."""
FIXED = b'{"armor_response":{"success":true}}'
FLOOR_FASTAPI = f"""
import sys, uvicorn
from fastapi import FastAPI, Request, Response
app = FastAPI(telemetry={{"tracing": False, "metrics": False, "logs": False}})
@app.post("/armor_interface_srv")
async def fixed(request: Request) -> Response:
    await request.body()
    return Response({FIXED!r}, media_type="application/json")
@app.get("/health")
async def health() -> dict[str, str]:
    return {{"status": "ok"}}
uvicorn.run(app, host="127.0.0.1", port=int(sys.argv[2]), log_level="warning", access_log=False)
"""
"""The floor of uvicorn and FastAPI for a directive: a route that reads the body and answers a
fixed body (FastAPI's telemetry off)."""
FLOOR_ASGI = f"""
import sys, uvicorn
async def app(scope, receive, send):
    if scope["type"] != "http":
        return
    while (await receive()).get("more_body", False):
        pass
    headers = [(b"content-type", b"application/json"), (b"content-length", b"{len(FIXED)}")]
    await send({{"type": "http.response.start", "status": 200, "headers": headers}})
    await send({{"type": "http.response.body", "body": {FIXED!r}}})
uvicorn.run(app, host="127.0.0.1", port=int(sys.argv[2]), log_level="warning", access_log=False)
"""
"""The floor of uvicorn alone: a plain ASGI app that reads the body and answers a fixed body."""
Directive = dict[str, Any]


def _request(
    command: str, first: str = "", second: str = "", *args: str, ref: str, client: str = "bench"
) -> Directive:
    return {
        "client_name": client,
        "reference_name": ref,
        "command": command,
        "primary_command_spec": first,
        "secondary_command_spec": second,
        "args": list(args),
    }


def _load(
    ref: str, path: str = "", iri: str = "http://ex.org/bench", buffered: bool = True
) -> Directive:
    return _request("LOAD", "FILE", "", path, iri, "false", "PELLET", str(buffered), ref=ref)


# Throughput -------------------------------------------------------------------------------------


def _directive(client: str, i: int) -> Directive:
    if i % 2 == 0:
        return _request(
            "ADD", "IND", "CLASS", f"{client}_{i}", f"Class_{i % 7}", ref="bench", client=client
        )
    return _request("QUERY", "IND", "", f"{client}_{i - 1}", ref="bench", client=client)


def run_clients(
    url: str, clients: int, seconds: float, path: str = "/armor_interface_srv", *, lean: bool = True
) -> float:
    """Requests per second that ``clients`` threads, one keep-alive connection each, complete.

    ``lean``: the standard library's ``http.client`` (about 40 µs of client work a request);
    otherwise ``httpx`` (several times that: with 8 threads in one process it, not the server,
    sets the pace on 2 cores).
    """
    counts = [0] * clients
    stop = time.perf_counter() + seconds
    failures: list[str] = []
    host, port = url.removeprefix("http://").split(":")

    def work(index: int) -> None:
        name = f"c{index}_{int(time.time() * 1e6) % 10**9}"
        i = 0
        if lean:
            connection = http.client.HTTPConnection(host, int(port), timeout=30)
            while time.perf_counter() < stop:
                if path == "/health":
                    connection.request("GET", path)
                else:
                    body = json.dumps({"armor_request": _directive(name, i)})
                    connection.request("POST", path, body, {"Content-Type": "application/json"})
                response = connection.getresponse()
                text = response.read()
                if response.status != 200 or (
                    path != "/health" and not json.loads(text)["armor_response"]["success"]
                ):
                    failures.append(text.decode())
                i += 1
            connection.close()
        else:
            with httpx.Client(base_url=url, timeout=30) as client:
                while time.perf_counter() < stop:
                    if path == "/health":
                        client.get(path).raise_for_status()
                    else:
                        reply = client.post(path, json={"armor_request": _directive(name, i)})
                        if not reply.json()["armor_response"]["success"]:
                            failures.append(reply.text)
                    i += 1
        counts[index] = i

    start = time.perf_counter()
    threads = [threading.Thread(target=work, args=(n,)) for n in range(clients)]
    for thread in threads:
        thread.start()
    for thread in threads:
        thread.join()
    elapsed = time.perf_counter() - start
    if failures:
        raise RuntimeError(f"{len(failures)} directives failed, e.g. {failures[0]}")
    return sum(counts) / elapsed


def _cpu_seconds(pid: int) -> float | None:
    """CPU time (user + system) a process has used so far; None where /proc is not there."""
    try:
        fields = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()
    except OSError:
        return None
    return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")


def run_measured(server: ChildServer, clients: int, seconds: float, path: str, lean: bool) -> str:
    """``run_clients``, with the server's CPU time per request: on a shared machine the rate
    depends on the other load, the CPU time much less."""
    rate, cpu, share = _measure(server, clients, seconds, path, lean)
    if cpu is None:
        return f"{rate:.0f}/s"
    return f"{rate:.0f}/s, server process {cpu:.0f} µs CPU a request ({share:.0%} of a core)"


def _measure(
    server: ChildServer, clients: int, seconds: float, path: str, lean: bool
) -> tuple[float, float | None, float]:
    """Requests per second, the server's CPU µs per request (None without /proc), and the
    share of a core the server used."""
    before = _cpu_seconds(server.process.pid)
    start = time.perf_counter()
    rate = run_clients(server.url, clients, seconds, path, lean=lean)
    elapsed = time.perf_counter() - start
    after = _cpu_seconds(server.process.pid)
    if before is None or after is None:
        return rate, None, 0.0
    used = after - before
    return rate, 1e6 * used / (rate * elapsed), used / elapsed


def in_process(seconds: float) -> float:
    with tempfile.TemporaryDirectory(prefix="engram-bench-") as data:
        engine = ArmorEngine(Store(Path(data) / "store"))
        engine.execute(ArmorDirectiveReq.model_validate(_load("bench")))
        stop, i = time.perf_counter() + seconds, 0
        start = time.perf_counter()
        while time.perf_counter() < stop:
            engine.execute(ArmorDirectiveReq.model_validate(_directive("local", i)))
            i += 1
        return i / (time.perf_counter() - start)


def throughput(seconds: float, *, lean: bool) -> None:
    client = "http.client" if lean else "httpx"
    print(f"# ARMOR simple directives (ADD IND CLASS / QUERY IND alternating), {client} clients")
    print(f"  {load_average()}")
    with tempfile.TemporaryDirectory(prefix="engram-bench-") as data:
        bare_server = ChildServer(data, BARE)
        server = ChildServer(data, SERVER)
        try:
            response = httpx.post(
                server.url + "/armor_interface_srv", json={"armor_request": _load("bench")}
            )
            assert response.json()["armor_response"]["success"], response.text
            run_clients(server.url, 8, 0.5, lean=lean)  # warm-up
            bare = [run_clients(bare_server.url, 8, seconds, "/health", lean=lean)]
            health = run_clients(server.url, 8, seconds, "/health", lean=lean)
            one = run_clients(server.url, 1, seconds, lean=lean)
            eight = run_clients(server.url, 8, seconds, lean=lean)
            bare.append(run_clients(bare_server.url, 8, seconds, "/health", lean=lean))
            cpu_bare = run_measured(bare_server, 8, seconds / 2, "/health", lean)
            cpu_directives = run_measured(server, 8, seconds / 2, "/armor_interface_srv", lean)
        finally:
            server.stop()
            bare_server.stop()
    local = in_process(seconds)
    ceiling = statistics.mean(bare)
    print(f"  1 client : {one:8.0f} directives/s over HTTP")
    verdict = "met" if eight >= 3000 else "NOT met"
    print(f"  8 clients: {eight:8.0f} directives/s over HTTP (target >= 3000: {verdict})")
    print(
        f"  baseline bare async endpoint, same uvicorn, 8 clients: {bare[0]:.0f} requests/s "
        f"before, {bare[1]:.0f} after (directives reach {eight / ceiling:.0%} of it)"
    )
    print(f"  for reference GET /health (a store read), 8 clients: {health:.0f} requests/s")
    print(f"  CPU, 8 clients: directives {cpu_directives}; bare endpoint {cpu_bare}")
    print(
        f"  baseline in-process engine, no HTTP, 1 thread: {local:8.0f} directives/s "
        f"(HTTP with 8 clients = {eight / local:.2f}x)"
    )
    print(f"  {load_average()}")


def against(other: Path, seconds: float, rounds: int, *, lean: bool, floors: bool) -> None:
    """The simple directives, 8 clients, against this checkout's server and the server of the
    checkout at ``other``, in turns (``rounds`` each), with the ratio of the medians; with
    ``floors``, the two floors (uvicorn and FastAPI answering a fixed body, uvicorn alone) in
    the same turns."""
    print(f"# ARMOR simple directives, 8 clients: this checkout against {other}")
    print(f"  {load_average()}")
    names = ["this", "other"] + (["fastapi floor", "uvicorn floor"] if floors else [])
    figures: dict[str, list[tuple[float, float | None]]] = {name: [] for name in names}
    with tempfile.TemporaryDirectory(prefix="engram-bench-") as data:
        servers = {
            "this": ChildServer(str(Path(data) / "this"), SERVER),
            "other": ChildServer(str(Path(data) / "other"), SERVER, root=other),
        }
        if floors:
            servers["fastapi floor"] = ChildServer(data, FLOOR_FASTAPI)
            servers["uvicorn floor"] = ChildServer(data, FLOOR_ASGI)
        try:
            for name, server in servers.items():
                if "floor" not in name:
                    response = httpx.post(
                        server.url + "/armor_interface_srv", json={"armor_request": _load("bench")}
                    )
                    assert response.json()["armor_response"]["success"], response.text
                run_clients(server.url, 8, 0.5, lean=lean)  # warm-up
            for _ in range(rounds):
                for name, server in servers.items():
                    rate, cpu, _ = _measure(server, 8, seconds, "/armor_interface_srv", lean)
                    figures[name].append((rate, cpu))
        finally:
            for server in servers.values():
                server.stop()
    medians = {}
    for name, runs in figures.items():
        rates = [rate for rate, _ in runs]
        cpus = [cpu for _, cpu in runs if cpu is not None]
        medians[name] = (statistics.median(rates), statistics.median(cpus) if cpus else None)
        shown = ", ".join(
            f"{rate:.0f}/s" + ("" if cpu is None else f" ({cpu:.0f} µs CPU)") for rate, cpu in runs
        )
        print(f"  {name:13s}: {shown}")
    (rate, cpu), (other_rate, other_cpu) = medians["this"], medians["other"]
    line = f"  median rate this ÷ other: {rate / other_rate:.2f}"
    if cpu is not None and other_cpu is not None:
        line += f"; median server CPU a request this ÷ other: {cpu / other_cpu:.2f}"
    print(line)
    print(f"  {load_average()}")


# REASON -----------------------------------------------------------------------------------------


def _inferred(store: Store, ref: str) -> set[str]:
    graph = reference_graph(ref, inferred=True)
    return {f"{q.subject} {q.predicate} {q.object}" for q in store.quads(graph=graph)}


def _execute(engine: ArmorEngine, *directives: Directive) -> None:
    result = engine.execute_list([ArmorDirectiveReq.model_validate(d) for d in directives])
    if not result.success:
        raise RuntimeError(f"directives failed: {result}")


def _full_reason(path: Path, work: Path, *, on_disk: bool) -> tuple[float, ArmorEngine]:
    """LOAD (not timed) then one REASON directive (timed) on a fresh engine and store."""
    engine = ArmorEngine(Store(tempfile.mkdtemp(dir=work)) if on_disk else Store())
    _execute(engine, _load("onto", str(path), EX.rstrip("#")))
    start = time.perf_counter()
    _execute(engine, _request("REASON", ref="onto"))
    return time.perf_counter() - start, engine


def _disk_io_floor(path: Path, work: Path, closure: bytes) -> tuple[float, float]:
    """What a full REASON on disk costs in store I/O alone, whatever the reasoner: reading the
    asserted graph and bulk writing the closure (as ``materialise`` does), on a store just
    LOADed the same way. Returns (read s, write s)."""
    engine = ArmorEngine(Store(tempfile.mkdtemp(dir=work)))
    _execute(engine, _load("onto", str(path), EX.rstrip("#")))
    start = time.perf_counter()
    engine.store.graph_ntriples(reference_graph("onto"))
    read = time.perf_counter() - start
    start = time.perf_counter()
    engine.store.fill_graph(reference_graph("onto", inferred=True), closure)
    return read, time.perf_counter() - start


def _new_object(n: int, ref: str = "onto") -> list[Directive]:
    """5 assertions about a new object, as ADD directives."""
    obj = f"bench_obj{n}"
    return [
        _request("ADD", "IND", "CLASS", obj, "Mug", ref=ref),
        _request("ADD", "OBJECTPROP", "IND", "inScene", obj, f"scene{n % 100}", ref=ref),
        _request("ADD", "DATAPROP", "IND", "score", obj, "DOUBLE", "0.5", ref=ref),
        _request("ADD", "DATAPROP", "IND", "level", obj, "INTEGER", "0", ref=ref),
        _request("ADD", "OBJECTPROP", "IND", "above", obj, f"scene{n % 100}_obj0", ref=ref),
    ]


def _summary(label: str, times: list[float]) -> str:
    times = sorted(times)
    p95 = times[min(len(times) - 1, int(0.95 * len(times)))]
    verdict = "met" if statistics.median(times) < 0.050 else "NOT met"
    return (
        f"  {label}, {len(times)} runs: median {1000 * statistics.median(times):.1f} ms, "
        f"p95 {1000 * p95:.1f} ms, max {1000 * times[-1]:.1f} ms (target < 50 ms: {verdict})"
    )


def _incremental(
    run_adds: Callable[[list[Directive]], None], runs: int, start_at: int
) -> tuple[list[float], list[float]]:
    """Times of REASON after 5 committed ADDs, and of one list [5 ADDs, REASON]."""
    after_adds, whole_list = [], []
    reason = _request("REASON", ref="onto")
    for n in range(runs):
        run_adds(_new_object(start_at + 2 * n))
        start = time.perf_counter()
        run_adds([reason])
        after_adds.append(time.perf_counter() - start)
        start = time.perf_counter()
        run_adds([*_new_object(start_at + 2 * n + 1), reason])
        whole_list.append(time.perf_counter() - start)
    return after_adds, whole_list


def _http_list(http: httpx.Client) -> Callable[[list[Directive]], None]:
    def send(directives: list[Directive]) -> None:
        response = http.post("/armor_interface_serialized_srv", json={"armor_requests": directives})
        if not response.json()["success"]:
            raise RuntimeError(response.text)

    return send


def reason(sizes: list[int], owlrl_50k: bool, runs: int) -> None:
    print(f"# REASON through the directive engine vs owlrl {owlrl.__version__}; {load_average()}")
    with tempfile.TemporaryDirectory(prefix="engram-bench-") as tmp:
        work = Path(tmp)
        engine: ArmorEngine | None = None
        path = work / "onto.nt"
        for size in sizes:
            path = work / f"onto-{size}.nt"
            path.write_text("\n".join(scene_ontology(size, seed=1)) + "\n")
            with_owlrl = size <= 10_000 or owlrl_50k
            times: dict[bool, list[float]] = {True: [], False: []}  # on disk?
            for on_disk in (True, False):  # one REASON of each before owlrl
                elapsed, engine = _full_reason(path, work, on_disk=on_disk)
                times[on_disk].append(elapsed)
            asserted = engine.store.graph_ntriples(reference_graph("onto"))
            triples = asserted.count(b"\n")
            print(f"\n## {triples} asserted triples ({path.name})")
            if with_owlrl:
                baseline, expected = owlrl_closure(asserted)
                same = _inferred(engine.store, "onto") == expected
                print(f"owlrl {baseline:.2f} s; identical inferences: {same}")
            else:
                print("owlrl not run at this size (--owlrl-50k runs it; about 100 s)")
            for _ in range(2):  # and two after
                for on_disk in (True, False):
                    elapsed, engine = _full_reason(path, work, on_disk=on_disk)
                    times[on_disk].append(elapsed)
            inferred = len(_inferred(engine.store, "onto"))
            floor = _disk_io_floor(
                path, work, engine.store.graph_ntriples(reference_graph("onto", inferred=True))
            )
            for on_disk in (True, False):
                ours = statistics.median(times[on_disk])
                kind = "on-disk store (as served)" if on_disk else "in-memory store"
                line = (
                    f"full REASON directive, {kind}: median {ours:.3f} s of "
                    f"{', '.join(f'{r:.3f}' for r in times[on_disk])} (+{inferred} inferred)"
                )
                if with_owlrl:
                    ratio = baseline / ours
                    verdict = "met" if ratio >= 100 else "NOT met"
                    line += f"; owlrl ÷ REASON {ratio:.0f}x (target >= 100x: {verdict})"
                print(line)
            read, write = floor
            line = (
                f"on-disk store I/O alone: read the asserted graph {read:.3f} s + bulk write "
                f"the closure {write:.3f} s = {read + write:.3f} s"
            )
            if with_owlrl:
                line += f" (owlrl ÷ that: {baseline / (read + write):.0f}x, with a free closure)"
            print(line)
        if engine is None or not runs:
            return
        print(f"\n## incremental REASON on the {sizes[-1]}-triple reference, on-disk store")
        _, engine = _full_reason(path, work, on_disk=True)
        local = engine
        after_adds, whole_list = _incremental(lambda d: _execute(local, *d), runs, 0)
        print(_summary("engine: REASON after 5 committed ADDs (buffered reasoner)", after_adds))
        print(_summary("engine: one list [5 ADDs, REASON]", whole_list))
        fresh = Store()
        with fresh.transaction() as tx:
            tx.inserts.extend(engine.store.quads(graph=reference_graph("onto")))
        materialise(
            fresh, asserted=reference_graph("onto"), inferred=reference_graph("onto", inferred=True)
        )
        same = _inferred(engine.store, "onto") == _inferred(fresh, "onto")
        print(f"  incremental result equals a full REASON: {same}")
        del engine
        server = ChildServer(str(work / "server"), SERVER)
        try:
            with httpx.Client(base_url=server.url, timeout=600) as http:
                send = _http_list(http)
                send([_load("onto", str(path), EX.rstrip("#"))])
                start = time.perf_counter()
                send([_request("REASON", ref="onto")])
                print(f"  HTTP: full REASON {time.perf_counter() - start:.3f} s")
                after_adds, whole_list = _incremental(send, runs, 0)
                print(
                    _summary("HTTP: REASON after 5 committed ADDs (buffered reasoner)", after_adds)
                )
                print(_summary("HTTP: one list [5 ADDs, REASON]", whole_list))
        finally:
            server.stop()
    print(f"  {load_average()}")


# Long lists -------------------------------------------------------------------------------------


def long_lists(lengths: list[int]) -> None:
    """Time one list of N ADD directives per length, over HTTP, against the first length."""
    print(f"\nlong directive lists, one request each ({load_average()})")
    with tempfile.TemporaryDirectory() as data:
        server = ChildServer(data, SERVER)
        try:
            with httpx.Client(base_url=server.url, timeout=600) as http:
                base: float | None = None
                for n in lengths:
                    ref = f"list{n}"
                    http.post("/armor_interface_srv", json={"armor_request": _load(ref)})
                    directives = [
                        _request("ADD", "IND", "CLASS", f"i{i}", f"C{i % 7}", ref=ref)
                        for i in range(n)
                    ]
                    start = time.perf_counter()
                    answer = http.post(
                        "/armor_interface_serialized_srv", json={"armor_requests": directives}
                    )
                    seconds = time.perf_counter() - start
                    responses = answer.json()["armor_responses"]
                    assert all(r["success"] for r in responses), answer.text[:300]
                    per = seconds / n
                    base = base or per
                    print(
                        f"  {n:6d} ADDs: {seconds:7.2f} s, {per * 1e6:6.0f} µs a directive, "
                        f"{per / base:4.2f} x the {lengths[0]:,}-directive list's per directive"
                    )
        finally:
            server.stop()


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument(
        "--only", choices=["throughput", "reason", "lists"], help="run one part only"
    )
    parser.add_argument("--lengths", default="1000,5000,20000", help="list lengths to time")
    parser.add_argument("--seconds", type=float, default=3.0, help="measuring time per figure")
    parser.add_argument("--owlrl-50k", action="store_true", help="run owlrl at 50k too (~100 s)")
    parser.add_argument("--runs", type=int, default=20, help="incremental REASONs to time")
    parser.add_argument("--sizes", default="10000,50000", help="ontology sizes in triples")
    parser.add_argument("--httpx", action="store_true", help="httpx clients, not http.client")
    parser.add_argument(
        "--against",
        type=Path,
        metavar="CHECKOUT",
        help="throughput only: this checkout's server against the one of another checkout",
    )
    parser.add_argument("--rounds", type=int, default=4, help="turns each, with --against")
    parser.add_argument(
        "--floors",
        action="store_true",
        help="with --against: also uvicorn and FastAPI answering a fixed body, and uvicorn alone",
    )
    options = parser.parse_args()
    if options.against is not None:
        against(
            options.against,
            options.seconds,
            options.rounds,
            lean=not options.httpx,
            floors=options.floors,
        )
        return
    if options.only in (None, "throughput"):
        throughput(options.seconds, lean=not options.httpx)
    if options.only in (None, "reason"):
        sizes = [int(s) for s in options.sizes.split(",")]
        reason(sizes, options.owlrl_50k, options.runs)
    if options.only in (None, "lists"):
        long_lists([int(n) for n in options.lengths.split(",")])


if __name__ == "__main__":
    main()
