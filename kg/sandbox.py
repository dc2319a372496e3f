"""Answer analysts' SPARQL with a time limit and a result-size limit.

pyoxigraph cannot cancel a query (it runs in Rust with the GIL released), so a time limit inside
the serving process could only stop waiting, not stop the work. Queries therefore run in worker
processes over a read-only snapshot of the on-disk store, a hard-linked backup taken after the
last write; a query past its limit is stopped by killing its worker, which is then replaced.
Snapshots are reused until the store changes and removed when no query reads them any more.

Queries are checked before they run: the text must parse as a query (an update does not), and
``SERVICE`` is refused because it would make the server fetch from arbitrary addresses.
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
from dataclasses import dataclass
from enum import Enum
from multiprocessing.connection import Connection
from pathlib import Path
from typing import Any

import pyoxigraph
from pyoxigraph import NamedNode, QueryBoolean, QuerySolutions

from kg.errors import (
    QueryError,
    QueryRefusedError,
    QuerySyntaxError,
    QueryTimeoutError,
    ResultTooLargeError,
    StoreError,
)
from kg.sparql_text import mentions_keyword
from kg.store import Store

__all__ = ["RESULT_FORMATS", "QueryForm", "QueryRunner", "QueryWork"]

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
class QueryWork:
    """A checked query, ready to run."""

    text: str
    form: QueryForm
    default_graphs: tuple[str, ...] | None = None
    named_graphs: tuple[str, ...] | None = None


@dataclass
class _Snapshot:
    path: Path
    generation: int
    readers: int = 0
    retired: bool = False


@dataclass
class _Worker:
    process: subprocess.Popen[bytes]
    connection: Connection

    def stop(self) -> None:
        self.process.kill()
        self.process.wait(timeout=5)
        self.connection.close()


class QueryRunner:
    """Runs read-only queries against ``store`` in killable worker processes.

    ``snapshot_dir`` must be on the same file system as the store so snapshots are hard links.
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
    ) -> None:
        if store.path is None:
            raise StoreError("the query runner needs an on-disk store to snapshot")
        if workers < 1:
            raise ValueError(f"workers: got {workers}, expected at least 1")
        self.store = store
        self.timeout_s = timeout_s
        self.max_result_bytes = max_result_bytes
        self._snapshot_dir = snapshot_dir
        shutil.rmtree(snapshot_dir, ignore_errors=True)  # leftovers of a previous run
        snapshot_dir.mkdir(parents=True)
        self._idle: queue.Queue[_Worker] = queue.Queue()
        for _ in range(workers):
            self._idle.put(self._start_worker())
        self._lock = threading.Lock()
        self._snapshot: _Snapshot | None = None
        self._checker = pyoxigraph.Store()  # empty: parses queries and tells their form

    # Checking ----------------------------------------------------------------------------------

    def check(
        self,
        text: str,
        *,
        default_graphs: list[str] | None = None,
        named_graphs: list[str] | None = None,
    ) -> QueryWork:
        """Parse ``text`` and return it with its form.

        Raises :class:`QuerySyntaxError` with the parser's position if it is not a query (which
        includes every update), and :class:`QueryRefusedError` if it calls ``SERVICE``.
        """
        if mentions_keyword(text, "SERVICE"):
            raise QueryRefusedError(
                "SERVICE (federated query) is disabled on this endpoint: it would let a query "
                "make the server contact other hosts"
            )
        try:
            result = self._checker.query(
                text,
                use_default_graph_as_union=default_graphs is None,
                default_graph=[NamedNode(g) for g in default_graphs]
                if default_graphs is not None
                else None,
                named_graphs=[NamedNode(g) for g in named_graphs]
                if named_graphs is not None
                else None,
            )
        except SyntaxError as error:
            raise QuerySyntaxError(f"not a valid SPARQL query: {error}") from None
        except ValueError as error:  # a malformed graph IRI
            raise QuerySyntaxError(str(error)) from None
        if isinstance(result, QuerySolutions):
            form = QueryForm.SOLUTIONS
        elif isinstance(result, QueryBoolean):
            form = QueryForm.BOOLEAN
        else:
            form = QueryForm.GRAPH
        return QueryWork(
            text,
            form,
            tuple(default_graphs) if default_graphs is not None else None,
            tuple(named_graphs) if named_graphs is not None else None,
        )

    # Running -----------------------------------------------------------------------------------

    def run(self, work: QueryWork, media_type: str) -> bytes:
        """Run a checked query and return its result serialised as ``media_type``.

        Raises :class:`QueryTimeoutError` when it takes longer than the time limit (waiting for a
        free worker included) and :class:`ResultTooLargeError` past the size limit.
        """
        formats = RESULT_FORMATS[work.form]
        if media_type not in formats:
            raise ValueError(f"media_type: got {media_type!r}, expected one of {list(formats)}")
        deadline = time.monotonic() + self.timeout_s
        snapshot = self._acquire_snapshot()
        try:
            worker = self._take_worker(deadline)
            try:
                job = {
                    "path": str(snapshot.path),
                    "text": work.text,
                    "graph_form": work.form is QueryForm.GRAPH,
                    "default_graphs": work.default_graphs,
                    "named_graphs": work.named_graphs,
                    "format": formats[media_type],
                    "limit": self.max_result_bytes,
                }
                worker.connection.send(job)
                if not worker.connection.poll(max(0.0, deadline - time.monotonic())):
                    raise QueryTimeoutError(
                        f"the query ran longer than the time limit of {self.timeout_s:g} s and "
                        "was stopped; narrow it, or add a LIMIT"
                    )
                status, payload = worker.connection.recv()
            except (QueryTimeoutError, EOFError, OSError):
                worker.stop()
                worker = self._start_worker()
                raise
            finally:
                self._idle.put(worker)
        finally:
            self._release_snapshot(snapshot)
        return _outcome(status, payload, self.max_result_bytes)

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

    def _take_worker(self, deadline: float) -> _Worker:
        try:
            return self._idle.get(timeout=max(0.0, deadline - time.monotonic()))
        except queue.Empty:
            raise QueryTimeoutError(
                f"no query worker became free within the time limit of {self.timeout_s:g} s"
            ) from None

    def _acquire_snapshot(self) -> _Snapshot:
        with self._lock:
            generation = self.store.generation
            current = self._snapshot
            if current is None or current.generation != generation:
                path = self._snapshot_dir / f"{generation}-{uuid.uuid4().hex[:8]}"
                self.store.backup(path)
                if current is not None:
                    current.retired = True
                    self._remove_if_unread(current)
                current = self._snapshot = _Snapshot(path, generation)
                log.debug("snapshot %s taken for queries", path.name)
            current.readers += 1
            return current

    def _release_snapshot(self, snapshot: _Snapshot) -> None:
        with self._lock:
            snapshot.readers -= 1
            self._remove_if_unread(snapshot)

    @staticmethod
    def _remove_if_unread(snapshot: _Snapshot) -> None:
        if snapshot.retired and snapshot.readers == 0:
            shutil.rmtree(snapshot.path, ignore_errors=True)


def _outcome(status: str, payload: Any, limit: int) -> bytes:
    if status == "ok":
        return bytes(payload)
    if status == "too_large":
        raise ResultTooLargeError(
            f"the result is larger than the limit of {limit} bytes; add a LIMIT or select less"
        )
    if status == "syntax":
        raise QuerySyntaxError(str(payload))
    raise QueryError(str(payload))
