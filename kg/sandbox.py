"""Answer callers' SPARQL with a time limit and a result-size limit, outside the server process.

pyoxigraph cannot cancel a query (it runs in Rust with the GIL released), so a time limit inside
the serving process could only stop waiting, not stop the work. Queries therefore run in worker
processes over a read-only snapshot of the on-disk store, a hard-linked backup taken after the
last write; a query past its limit is stopped by killing its worker, which is then replaced.
Snapshots are reused until the store changes and removed when no query reads them any more.

Nothing of a caller's text is parsed in the server: the worker (:mod:`kg._query_worker`) checks
the nesting depth, parses, refuses updates and ``SERVICE`` as Oxigraph's parser reads them,
evaluates and serialises, all inside the time limit, and cannot open Internet sockets. A worker
that dies (a parser stack overflow, say) is replaced and the query answers
:class:`QueryWorkerCrashedError`.
"""

import logging
import queue
import shutil
import socket
import subprocess
import sys
import threading
import time
import uuid
from collections.abc import Mapping
from dataclasses import dataclass, field
from enum import Enum
from multiprocessing.connection import Connection
from pathlib import Path
from typing import Any

from kg.errors import (
    QueryError,
    QueryRefusedError,
    QuerySyntaxError,
    QueryTimeoutError,
    QueryTooDeepError,
    QueryTooLongError,
    QueryWorkerCrashedError,
    ResultTooLargeError,
    StoreError,
    UnsupportedQueryError,
)
from kg.store import Store

__all__ = ["RESULT_FORMATS", "QueryAnswer", "QueryForm", "QueryRunner"]

log = logging.getLogger(__name__)


class QueryForm(Enum):
    """What a query returns, which decides the formats it can be written in."""

    SOLUTIONS = "solutions"  # SELECT
    BOOLEAN = "boolean"  # ASK
    GRAPH = "graph"  # CONSTRUCT, DESCRIBE


RESULT_FORMATS: dict[QueryForm, dict[str, str]] = {
    QueryForm.SOLUTIONS: {
        "application/sparql-results+json": "JSON",
        "application/sparql-results+xml": "XML",
        "text/csv": "CSV",
        "text/tab-separated-values": "TSV",
    },
    QueryForm.GRAPH: {
        "text/turtle": "TURTLE",
        "application/n-triples": "N_TRIPLES",
        "application/rdf+xml": "RDF_XML",
        "application/ld+json": "JSON_LD",
    },
}
RESULT_FORMATS[QueryForm.BOOLEAN] = RESULT_FORMATS[QueryForm.SOLUTIONS]
"""Media types each query form can be answered in, the first being the default."""


@dataclass(frozen=True)
class QueryAnswer:
    """A query's form and its result, serialised as ``media_type``.

    ``media_type`` is None (and ``body`` empty) when the caller accepts no media type of the
    query's form: the query was not evaluated.
    """

    form: QueryForm
    media_type: str | None
    body: bytes


@dataclass
class _Snapshot:
    path: Path
    generation: int
    readers: int = 0
    retired: bool = False
    taken_at: float = field(default_factory=time.monotonic)


@dataclass
class _Worker:
    process: subprocess.Popen[bytes]
    connection: Connection

    def stop(self) -> None:
        if self.process.poll() is None:
            self.process.kill()
        try:
            self.process.wait(timeout=5)
        except subprocess.TimeoutExpired:  # killed but not yet reaped (a loaded machine)
            log.warning("query worker %d not reaped 5 s after SIGKILL", self.process.pid)
        self.connection.close()


class QueryRunner:
    """Runs read-only queries against ``store`` in killable worker processes.

    ``snapshot_dir`` must be on the same file system as the store so snapshots are hard links.
    ``max_query_chars`` and ``max_depth`` bound the text a worker is given to parse.
    ``snapshot_max_age_s`` above 0 lets a query read a snapshot up to that old instead of
    waiting for a new one (a store backup, 30-400 ms under load) when writers keep committing,
    and the previous snapshot while the next one is being taken (so a query may miss commits
    of the last ``snapshot_max_age_s`` plus one backup's time).
    Raises :class:`StoreError` for an in-memory store, which no other process can read.
    """

    def __init__(
        self,
        store: Store,
        *,
        snapshot_dir: Path,
        workers: int = 2,
        timeout_s: float = 10.0,
        max_result_bytes: int = 64 * 1024 * 1024,
        max_query_chars: int = 1024 * 1024,
        max_depth: int = 128,
        snapshot_max_age_s: float = 0.0,
    ) -> None:
        if store.path is None:
            raise StoreError("the query runner needs an on-disk store to snapshot")
        if workers < 1:
            raise ValueError(f"workers: got {workers}, expected at least 1")
        self.store = store
        self.timeout_s = timeout_s
        self.max_result_bytes = max_result_bytes
        self.max_query_chars = max_query_chars
        self.max_depth = max_depth
        self.snapshot_max_age_s = snapshot_max_age_s
        """A snapshot this young serves queries though the store changed since (0: never)."""
        self._snapshot_dir = snapshot_dir
        shutil.rmtree(snapshot_dir, ignore_errors=True)  # leftovers of a previous run
        snapshot_dir.mkdir(parents=True)
        self._idle: queue.Queue[_Worker] = queue.Queue()
        for _ in range(workers):
            self._idle.put(self._start_worker())
        self._lock = threading.Lock()
        self._changed = threading.Condition(self._lock)
        self._taking = False
        self._snapshot: _Snapshot | None = None

    # Running -----------------------------------------------------------------------------------

    def run(
        self,
        text: str,
        *,
        media_types: Mapping[QueryForm, str],
        default_graphs: list[str] | None = None,
        named_graphs: list[str] | None = None,
        graph_data: Mapping[str, bytes] | None = None,
        timeout_s: float | None = None,
    ) -> QueryAnswer:
        """Check and run ``text`` in a worker; return its result in the form's media type.

        ``media_types`` gives, per query form, the media type the caller wants; a form missing
        from it is answered with ``media_type=None``. The query reads the store's last committed
        state, or, when ``graph_data`` is given, those named graphs (N-Triples) only.
        ``timeout_s`` can shorten the time limit, never lengthen it.

        Raises :class:`QueryTooLongError` and :class:`QueryTooDeepError` for text past the
        limits, :class:`QuerySyntaxError` (with the parser's position) for text that is not a
        query (every update included), :class:`QueryRefusedError` for ``SERVICE``,
        :class:`UnsupportedQueryError` for a query Oxigraph cannot evaluate (an unknown
        function), :class:`QueryTimeoutError` past the time limit (waiting for a free worker
        included), :class:`ResultTooLargeError` past the size limit, and
        :class:`QueryWorkerCrashedError` if the worker died.
        """
        if len(text) > self.max_query_chars:
            raise QueryTooLongError(
                f"query: {len(text)} characters, longer than the limit of {self.max_query_chars}"
            )
        formats: dict[str, str] = {}
        for form, media_type in media_types.items():
            if media_type not in RESULT_FORMATS[form]:
                raise ValueError(
                    f"media_types[{form.value}]: got {media_type!r}, "
                    f"expected one of {list(RESULT_FORMATS[form])}"
                )
            formats[form.value] = RESULT_FORMATS[form][media_type]
        limit_s = self.timeout_s if timeout_s is None else min(timeout_s, self.timeout_s)
        deadline = time.monotonic() + limit_s
        job: dict[str, Any] = {
            "text": text,
            "default_graphs": tuple(default_graphs) if default_graphs is not None else None,
            "named_graphs": tuple(named_graphs) if named_graphs is not None else None,
            "formats": formats,
            "limit": self.max_result_bytes,
            "max_depth": self.max_depth,
            "graph_data": dict(graph_data) if graph_data is not None else None,
        }
        snapshot = self._acquire_snapshot() if graph_data is None else None
        try:
            if snapshot is not None:
                job["path"] = str(snapshot.path)
            status, form, payload = self._exchange(job, deadline, limit_s)
        finally:
            if snapshot is not None:
                self._release_snapshot(snapshot)
        return _outcome(status, form, payload, media_types, self.max_result_bytes)

    def snapshot_is_current(self) -> bool:
        """True if the last snapshot holds the store's latest commit (a query needs no new one).

        A caller reading a few small graphs can send them as ``graph_data`` instead when this is
        False: a snapshot costs a store backup and a fresh open in the worker.
        """
        with self._lock:
            return self._snapshot is not None and self._snapshot.generation == self.store.generation

    def _exchange(self, job: dict[str, Any], deadline: float, limit_s: float) -> Any:
        worker = self._take_worker(deadline, limit_s)
        try:
            worker.connection.send(job)
            if not worker.connection.poll(max(0.0, deadline - time.monotonic())):
                raise QueryTimeoutError(
                    f"the query ran longer than the time limit of {limit_s:g} s and "
                    "was stopped; narrow it, or add a LIMIT"
                )
            return worker.connection.recv()
        except QueryTimeoutError:
            worker = self._replace(worker)
            raise
        except (EOFError, OSError):
            code = worker.process.poll()
            worker = self._replace(worker)
            log.warning("a query worker died (exit status %s); replaced", code)
            raise QueryWorkerCrashedError(
                "the query stopped the process evaluating it (exit status "
                f"{code}); the server is unaffected and a new worker is ready"
            ) from None
        finally:
            self._idle.put(worker)

    def _replace(self, worker: _Worker) -> _Worker:
        worker.stop()
        return self._start_worker()

    def close(self) -> None:
        """Stop the workers and remove the snapshots."""
        while True:
            try:
                worker = self._idle.get_nowait()
            except queue.Empty:
                break
            worker.stop()
        shutil.rmtree(self._snapshot_dir, ignore_errors=True)

    def _start_worker(self) -> _Worker:
        ours, theirs = socket.socketpair()
        process = subprocess.Popen(
            [sys.executable, "-m", "kg._query_worker", str(theirs.fileno())],
            pass_fds=(theirs.fileno(),),
            stdin=subprocess.DEVNULL,
        )
        theirs.close()
        return _Worker(process, Connection(ours.detach()))

    def _take_worker(self, deadline: float, limit_s: float) -> _Worker:
        try:
            worker = self._idle.get(timeout=max(0.0, deadline - time.monotonic()))
        except queue.Empty:
            raise QueryTimeoutError(
                f"no query worker became free within the time limit of {limit_s:g} s"
            ) from None
        if worker.process.poll() is not None:  # died while idle: not this query's doing
            worker = self._replace(worker)
        return worker

    def _acquire_snapshot(self) -> _Snapshot:
        """A snapshot holding at least every commit made before this call.

        One backup is taken at a time, outside the lock: queries that arrive while it runs wait
        for the next one, which then serves them all, instead of each taking its own in turn
        (with writers committing all the time, every query found the store changed and queued
        behind the others' backups).
        """
        wanted = self.store.generation
        with self._changed:
            while True:
                current = self._snapshot
                if current is not None and (
                    current.generation >= wanted
                    or time.monotonic() - current.taken_at <= self.snapshot_max_age_s
                ):
                    current.readers += 1
                    return current
                if not self._taking:
                    self._taking = True
                    break
                if current is not None and self.snapshot_max_age_s > 0:
                    current.readers += 1  # stale while the next backup is taken, by choice
                    return current
                self._changed.wait()
        try:
            generation = self.store.generation  # the backup holds at least these commits
            path = self._snapshot_dir / f"{generation}-{uuid.uuid4().hex[:8]}"
            self.store.backup(path)
        except BaseException:
            with self._changed:
                self._taking = False
                self._changed.notify_all()
            raise
        with self._changed:
            self._taking = False
            previous = self._snapshot
            if previous is not None:
                previous.retired = True
                self._remove_if_unread(previous)
            current = self._snapshot = _Snapshot(path, generation, readers=1)
            self._changed.notify_all()
        log.debug("snapshot %s taken for queries", path.name)
        return current

    def _release_snapshot(self, snapshot: _Snapshot) -> None:
        with self._lock:
            snapshot.readers -= 1
            self._remove_if_unread(snapshot)

    @staticmethod
    def _remove_if_unread(snapshot: _Snapshot) -> None:
        if snapshot.retired and snapshot.readers == 0:
            shutil.rmtree(snapshot.path, ignore_errors=True)


_FAILURES: dict[str, type[QueryError]] = {
    "syntax": QuerySyntaxError,
    "refused": QueryRefusedError,
    "too_deep": QueryTooDeepError,
    "unsupported": UnsupportedQueryError,
}


def _outcome(
    status: str,
    form: str | None,
    payload: Any,
    media_types: Mapping[QueryForm, str],
    limit: int,
) -> QueryAnswer:
    if status == "ok":
        query_form = QueryForm(form)
        return QueryAnswer(query_form, media_types[query_form], bytes(payload))
    if status == "not_acceptable":
        return QueryAnswer(QueryForm(form), None, b"")
    if status == "too_large":
        raise ResultTooLargeError(
            f"the result is larger than the limit of {limit} bytes; add a LIMIT or select less"
        )
    raise _FAILURES.get(status, QueryError)(str(payload))
