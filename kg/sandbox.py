"""Answer callers' SPARQL with a time limit and a result-size limit, outside the server process.

pyoxigraph cannot cancel a query (it runs in Rust with the GIL released), so a time limit inside
the serving process could only stop waiting, not stop the work. Queries therefore run in worker
processes, each over its own copy of the on-disk store (a hard-linked backup, taken when the
worker starts); a query past its limit is stopped by killing its worker, which is then replaced.
Before a query the worker replays into its copy the commits made since (the store's
:meth:`~kg.Store.commit_log`: a few quads each), so every query sees every commit made before
it at the cost of the replay, not of a backup and a fresh open per commit. A copy too far
behind to replay
(a bulk load since, or more than :data:`_REPLAY_MAX` quads) is taken afresh.

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
import time
import uuid
from collections.abc import Mapping
from dataclasses import dataclass
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
class _Worker:
    process: subprocess.Popen[bytes]
    connection: Connection
    copy: Path | None = None
    """Its private copy of the store (a backup it opens read-write and replays commits into)."""
    generation: int = -1
    """The store generation its copy holds every commit of."""
    caught_up_at: float = 0.0

    def stop(self) -> None:
        if self.process.poll() is None:
            self.process.kill()
        try:
            self.process.wait(timeout=5)
        except subprocess.TimeoutExpired:  # killed but not yet reaped (a loaded machine)
            log.warning("query worker %d not reaped 5 s after SIGKILL", self.process.pid)
        self.connection.close()
        if self.copy is not None:
            shutil.rmtree(self.copy, ignore_errors=True)


_REPLAY_MAX = 50_000
"""Above this many quads to replay, a worker's copy is taken afresh (a backup) instead."""


class QueryRunner:
    """Runs read-only queries against ``store`` in killable worker processes.

    ``snapshot_dir`` must be on the same file system as the store so the workers' copies are
    hard links. ``max_query_chars`` and ``max_depth`` bound the text a worker is given to parse.
    ``snapshot_max_age_s`` above 0 lets a worker skip replaying commits when it last caught up
    less than that long ago (a query may then miss the commits of the last
    ``snapshot_max_age_s``); 0, the default, makes every query see every earlier commit.
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
        """A copy caught up this recently serves queries though the store changed (0: never)."""
        self._snapshot_dir = snapshot_dir
        shutil.rmtree(snapshot_dir, ignore_errors=True)  # leftovers of a previous run
        snapshot_dir.mkdir(parents=True)
        self._commits = store.commit_log()
        self._idle: queue.Queue[_Worker] = queue.Queue()
        for _ in range(workers):
            self._idle.put(self._start_worker())

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
        if graph_data is None:  # what the store keeps lazily is written before the copy reads
            self.store.settle_reads()
        status, form, payload = self._exchange(
            job, deadline, limit_s, from_store=graph_data is None
        )
        return _outcome(status, form, payload, media_types, self.max_result_bytes)

    def snapshot_is_current(self) -> bool:
        """True if a query can read the store's latest commit without a new copy of the store.

        A caller reading a few small graphs can send them as ``graph_data`` instead when this is
        False: a copy costs a store backup and a fresh open in the worker.
        """
        idle = list(self._idle.queue)  # a worker busy with a query has caught up recently
        oldest = min((w.generation if w.copy else -1 for w in idle), default=-1)
        return oldest >= self._commits.floor

    def _exchange(
        self, job: dict[str, Any], deadline: float, limit_s: float, *, from_store: bool
    ) -> Any:
        worker = self._take_worker(deadline, limit_s)
        try:
            if from_store:
                self._catch_up(worker, job)
            answer = self._ask(worker, job, deadline, limit_s)
            if from_store and answer[0] == "replay_failed":  # its copy is unusable: a new one
                log.warning("query worker %d could not catch up: %s", worker.process.pid, answer[2])
                worker.generation = -1
                job.pop("retire", None)
                self._catch_up(worker, job)
                answer = self._ask(worker, job, deadline, limit_s)
            if from_store:
                worker.generation = max(worker.generation, job["generation"])
            return answer
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

    @staticmethod
    def _ask(worker: _Worker, job: dict[str, Any], deadline: float, limit_s: float) -> Any:
        worker.connection.send(job)
        if not worker.connection.poll(max(0.0, deadline - time.monotonic())):
            raise QueryTimeoutError(
                f"the query ran longer than the time limit of {limit_s:g} s and "
                "was stopped; narrow it, or add a LIMIT"
            )
        return worker.connection.recv()

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

    def _catch_up(self, worker: _Worker, job: dict[str, Any]) -> None:
        """Add to ``job`` the worker's copy of the store and the commits it must replay first
        to hold every commit made before this call; take the copy afresh if it cannot."""
        wanted = self.store.generation
        now = time.monotonic()
        if (
            worker.copy is not None
            and self.snapshot_max_age_s > 0
            and now - worker.caught_up_at <= self.snapshot_max_age_s
        ):
            wanted = worker.generation  # stale by choice
        else:
            worker.caught_up_at = now
        commits = None
        if worker.copy is not None and worker.generation >= 0:
            commits = self._commits.since(worker.generation, wanted)
            if commits is not None and sum(c.size for c in commits) > _REPLAY_MAX:
                commits = None
        if commits is None:
            if worker.copy is not None:
                job["retire"] = str(worker.copy)  # the worker closes and removes it
            generation = self.store.generation  # the backup holds at least these commits
            path = self._snapshot_dir / f"{worker.process.pid}-{generation}-{uuid.uuid4().hex[:8]}"
            self.store.backup(path)
            worker.copy, worker.generation = path, generation
            commits = self._commits.since(generation, wanted) or []
            log.debug("query worker %d: a new copy of the store", worker.process.pid)
        job["path"] = str(worker.copy)
        job["replay"] = [(c.inserts, c.update) for c in commits]
        job["generation"] = max(wanted, worker.generation)


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
