"""The one place that touches ``pyoxigraph.Store``.

>>> from ontologies.vocab import MEMORY, engram, RDFS_LABEL
>>> from pyoxigraph import Literal
>>> store = Store()                      # in memory; Store(path) opens or creates a directory
>>> with store.transaction() as tx:
...     tx.insert(engram("Scene-1"), RDFS_LABEL, Literal("a scene"), MEMORY)
>>> store.select("graph_sizes")[0]["triples"].value
'1'
"""

import contextlib
import fcntl
import functools
import logging
import os
import select
import threading
from collections.abc import Callable, Iterable, Iterator, Mapping, Sequence
from concurrent.futures import ThreadPoolExecutor
from contextlib import contextmanager
from pathlib import Path
from typing import TYPE_CHECKING, Any

import pyoxigraph
from pyoxigraph import (
    Literal,
    NamedNode,
    Quad,
    QueryBoolean,
    QuerySolutions,
    QueryTriples,
    Triple,
)

import sparql
from kg.commit_log import CommitLog
from kg.errors import (
    QueryRefusedError,
    QuerySyntaxError,
    StoreError,
    StoreLockedError,
    TransactionError,
)
from kg.literals import (
    from_store,
    kept_text,
    ntriples_to_store,
    quad_from_store,
    quads_to_store,
    to_store,
)
from kg.sparql_text import bind_table, bind_values, mentions_keyword
from kg.transaction import Transaction
from ontologies.vocab import BULK_WRITES, RDF_TYPE, UNFINISHED_BULK_WRITE

if TYPE_CHECKING:
    from kg.remote import RemoteDataset

__all__ = ["LARGE_WRITE_QUADS", "Binding", "Store", "Tracer", "update_text"]

log = logging.getLogger(__name__)

LARGE_WRITE_QUADS = 10_000
"""A transaction of at least this many quads is flushed in the background once written, so that
the writes after it go to an empty memtable and cost what they cost in a settled store."""

Binding = NamedNode | Literal
Tracer = Callable[[str, str, Mapping[str, Binding]], None]
"""Called with (kind, text, bindings) for every query ("query") and write ("update", "extend")."""


class Store:
    """An Engram knowledge graph: an on-disk Oxigraph store, or an in-memory one for tests.

    Reads go through named queries from ``sparql/`` with bound terms; writes go through
    :meth:`transaction`. Writers are serialised by a lock, so a transaction that reads the store
    while it is being built sees no other writer's half-finished work.

    Raises :class:`StoreLockedError` if another process holds the directory, and
    :class:`StoreError` if the directory holds something that is not a store.

    ``backend`` is a memory on a shared SPARQL server instead (:func:`kg.fleet.open_remote`
    builds one): the same calls, over HTTP.
    """

    def __init__(
        self,
        path: str | os.PathLike[str] | None = None,
        *,
        tracer: Tracer | None = None,
        backend: "RemoteDataset | None" = None,
    ):
        self.path = Path(path) if path is not None and backend is None else None
        self.remote = backend
        try:
            if self.path is not None:
                self.path.mkdir(parents=True, exist_ok=True)
            self._store: pyoxigraph.Store | RemoteDataset = (
                backend
                if backend is not None
                else pyoxigraph.Store(str(self.path))
                if self.path
                else pyoxigraph.Store()
            )
        except OSError as error:
            if "lock" in str(error).lower():
                raise StoreLockedError(
                    f"the store at {self.path} is open in another process "
                    "(is `engram serve` running?); stop it or talk to it over HTTP"
                ) from error
            raise StoreError(f"cannot open the store at {self.path}: {error}") from error
        self._write_lock = threading.Lock()
        self._read_barriers: list[Callable[[], None]] = []
        self._in_write = threading.local()
        self._tracers: list[Tracer] = [tracer] if tracer else []
        self._generation = 0
        self._committer: ThreadPoolExecutor | None = None
        self._flusher: threading.Thread | None = None
        self._flush_lock = threading.Lock()
        """One flush (or backup, whose checkpoint flushes) at a time: two at once on one
        RocksDB store can wait on each other for ever."""
        self._commit_log: CommitLog | None = None
        if self.path is not None or (backend is not None and not backend.read_only):
            self.recover_bulk_writes()

    @property
    def generation(self) -> int:
        """How many transactions this object has committed; a cheap "has anything changed" test."""
        return self._generation

    def commit_log(self) -> CommitLog:
        """The log of this store's commits from now on (:mod:`kg.commit_log`), started by the
        first call: the SPARQL workers' copies of the store catch up from it."""
        with self._write_lock:
            if self._commit_log is None:
                self._commit_log = CommitLog()
                self._commit_log.unrecorded(self._generation)
            return self._commit_log

    def _unrecorded_write(self) -> None:
        """Count a write the commit log cannot replay (a bulk load, a recovery)."""
        self._generation += 1
        if self._commit_log is not None:
            self._commit_log.unrecorded(self._generation)

    # Read barriers -----------------------------------------------------------------------------

    def add_read_barrier(self, barrier: Callable[[], None]) -> None:
        """Call ``barrier`` before every read of this store (see :meth:`settle_reads`)."""
        self._read_barriers.append(barrier)

    def settle_reads(self) -> None:
        """Bring triples kept up to date lazily (the scene memory's score view) up to date, by
        running the read barriers; every read method calls it first, and so does the SPARQL
        endpoint before its workers catch up. A read made inside a transaction or a barrier of
        this thread skips it: it belongs to the write in progress, which reads what it writes."""
        local = self._in_write
        if self._read_barriers and not getattr(local, "depth", 0):
            local.depth = 1  # as _writing() does: every read calls this, kept short
            try:
                for barrier in self._read_barriers:
                    barrier()
            finally:
                local.depth = 0

    @contextmanager
    def _writing(self) -> Iterator[None]:
        local = self._in_write
        local.depth = getattr(local, "depth", 0) + 1
        try:
            yield
        finally:
            local.depth -= 1

    # Tracing -----------------------------------------------------------------------------------

    @contextmanager
    def tracing(self, tracer: Tracer) -> Iterator[None]:
        """Call ``tracer`` for every query and write made inside the ``with`` block."""
        self._tracers.append(tracer)
        try:
            yield
        finally:
            self._tracers.remove(tracer)

    def _trace(self, kind: str, text: str, bindings: Mapping[str, Binding]) -> None:
        for tracer in self._tracers:
            tracer(kind, text, bindings)

    # Reads -------------------------------------------------------------------------------------

    def select(self, name: str, **bindings: Binding) -> list[dict[str, Binding]]:
        """Run the SELECT query ``sparql/<name>.rq`` with ``bindings`` and return its rows.

        Each row maps variable names to terms; unbound variables are absent from the row.
        """
        return self._select(sparql.load(name), bindings, name)

    def select_each(
        self, name: str, column: str, terms: Sequence[Binding], **bindings: Binding
    ) -> list[dict[str, Binding]]:
        """Run ``sparql/<name>.rq`` once for all ``terms`` bound to ``column`` (one ``VALUES``
        row each, with ``bindings`` in every row): one round trip instead of one per term."""
        if not terms:
            return []
        names = [column, *bindings]
        rows = [[term, *bindings.values()] for term in terms]
        text = bind_table(sparql.load(name), names, rows)
        return self._select(text, {}, name)

    def _select(
        self, text: str, bindings: Mapping[str, Binding], name: str = "query"
    ) -> list[dict[str, Binding]]:
        result = self._query(text, bindings)
        if not isinstance(result, QuerySolutions):
            raise TypeError(f"query {name!r} is not a SELECT query")
        names = [variable.value for variable in result.variables]
        return [
            {n: from_store(term) for n in names if (term := row[n]) is not None} for row in result
        ]

    def ask(self, name: str, **bindings: Binding) -> bool:
        """Run the ASK query ``sparql/<name>.rq`` with ``bindings``."""
        result = self._query(sparql.load(name), bindings)
        if not isinstance(result, QueryBoolean):
            raise TypeError(f"query {name!r} is not an ASK query")
        return bool(result)

    def construct(self, name: str, **bindings: Binding) -> list[Triple]:
        """Run the CONSTRUCT or DESCRIBE query ``sparql/<name>.rq`` with ``bindings``."""
        result = self._query(sparql.load(name), bindings)
        if not isinstance(result, QueryTriples):
            raise TypeError(f"query {name!r} is not a CONSTRUCT or DESCRIBE query")
        return [Triple(t.subject, t.predicate, from_store(t.object)) for t in result]

    def _query(self, text: str, bindings: Mapping[str, Binding]) -> Any:
        self.settle_reads()
        text = bind_values(text, {name: to_store(term) for name, term in bindings.items()})
        self._trace("query", text, bindings)
        return self._store.query(text, use_default_graph_as_union=True)

    def query_graphs(
        self,
        text: str,
        *,
        graphs: Sequence[NamedNode],
        bindings: Mapping[str, Binding] | None = None,
    ) -> QuerySolutions | QueryBoolean | QueryTriples:
        """Run SPARQL query ``text`` (a caller's, not a stored one) over chosen graphs only.

        The union of ``graphs`` is the default graph, and ``GRAPH`` reaches only those graphs.
        Raises :class:`QuerySyntaxError` (with the parser's position) for text that does not
        parse or is an update, and :class:`QueryRefusedError` for ``SERVICE``.

        >>> from ontologies.vocab import reference_graph
        >>> store = Store()
        >>> store.query_graphs("ASK { ?s ?p ?o }", graphs=[reference_graph("r")]).__bool__()
        False
        """
        if mentions_keyword(text, "SERVICE"):
            raise QueryRefusedError("SERVICE is refused: queries may only read this store")
        self.settle_reads()
        text = bind_values(text, bindings or {})
        self._trace("query", text, bindings or {})
        try:
            result: QuerySolutions | QueryBoolean | QueryTriples = self._store.query(
                text, default_graph=list(graphs), named_graphs=list(graphs)
            )
        except SyntaxError as error:
            raise QuerySyntaxError(str(error)) from None
        return result

    def quads(
        self,
        subject: NamedNode | None = None,
        predicate: NamedNode | None = None,
        obj: NamedNode | Literal | None = None,
        graph: NamedNode | None = None,
    ) -> Iterator[Quad]:
        """The stored quads matching a pattern (``None`` matches anything), literals as written
        (:mod:`kg.literals`)."""
        self.settle_reads()
        found = self._store.quads_for_pattern(subject, predicate, to_store(obj), graph)
        return map(quad_from_store, found)

    def settle(self) -> None:
        """On a SPARQL server, after a failed write: read the revision back and let the
        listeners rebuild what they hold (:meth:`kg.remote.RemoteDataset.settle`) before anything
        is computed on it; a no-op otherwise. Call it before taking locks the listeners take.
        Raises :class:`StoreUnavailableError` while the server is still away."""
        if self.remote is not None:
            self.remote.settle()

    def named_graphs(self) -> list[NamedNode]:
        """The named graphs that hold at least one triple."""
        return [g for g in self._store.named_graphs() if isinstance(g, NamedNode)]

    def graph_sizes(self) -> dict[str, int]:
        """Triples per named graph, by graph IRI."""
        return {row["graph"].value: int(row["triples"].value) for row in self.select("graph_sizes")}

    def graph_ntriples(self, graph: NamedNode) -> bytes:
        """The triples of one named graph as N-Triples (one triple a line, canonical literals).

        Serialised by Oxigraph itself, so a reader that wants the whole graph as text (the OWL 2
        RL reasoner compares and reasons over it) skips building one term object per triple.
        Raises ``TypeError`` if ``graph`` is not a NamedNode.

        >>> from ontologies.vocab import MEMORY, RDFS_LABEL, engram
        >>> store = Store()
        >>> with store.transaction() as tx:
        ...     tx.insert(engram("a"), RDFS_LABEL, Literal("x"), MEMORY)
        >>> store.graph_ntriples(MEMORY).decode()
        '<https://w3id.org/engram/ontology#a> <http://www.w3.org/2000/01/rdf-schema#label> "x" .\\n'
        """
        if not isinstance(graph, NamedNode):
            raise TypeError(f"graph must be a NamedNode naming an Engram graph, got {graph!r}")
        self.settle_reads()
        self._trace("query", f"DUMP GRAPH {graph} AS N-Triples", {})
        dumped = self._store.dump(format=pyoxigraph.RdfFormat.N_TRIPLES, from_graph=graph) or b""
        return kept_text(dumped)

    # Writes ------------------------------------------------------------------------------------

    @contextmanager
    def transaction(
        self, *, alongside: Callable[[], object] | None = None
    ) -> Iterator[Transaction]:
        """Collect changes in the ``with`` block and apply them atomically when it ends.

        If the block raises, nothing is written. If the write itself fails,
        :class:`TransactionError` is raised and the store is unchanged.

        A transaction of at least :data:`LARGE_WRITE_QUADS` quads is flushed in the background
        once written (:meth:`flush_in_background`).

        ``alongside`` is called in this thread while another thread applies the write (Oxigraph
        releases the GIL while it writes): work that must be done when the transaction returns
        but does not feed it, such as in-memory bookkeeping. Its exceptions propagate once the
        write has finished, and they do not undo the write.
        """
        self.settle()
        with self._write_lock, self._writing():
            tx = Transaction()
            yield tx
            write = self._prepare(tx)
            if len(tx.inserts) + len(tx.deletes) >= LARGE_WRITE_QUADS:
                write = self._flushed_after(write)
            if alongside is None:
                write()
                return
            if self._committer is None:
                self._committer = ThreadPoolExecutor(1, thread_name_prefix="engram-commit")
            started = threading.Event()

            def start_and_write() -> None:
                started.set()
                write()

            done = self._committer.submit(start_and_write)
            # Waiting here hands the GIL to the writer, which keeps it only until Oxigraph
            # releases it; otherwise it could wait a whole switch interval (5 ms) to start.
            started.wait()
            try:
                alongside()
            finally:
                done.result()

    def _flushed_after(self, write: Callable[[], None]) -> Callable[[], None]:
        def write_then_flush() -> None:
            write()
            self.flush_in_background()

        return write_then_flush

    def _prepare(self, tx: Transaction) -> Callable[[], None]:
        """The write that commits ``tx``, with every read and every Python step done first."""
        if tx.is_empty:
            return lambda: None
        inserts = quads_to_store(tx.inserts)
        deletes = quads_to_store(tx.deletes)
        for pattern in tx.patterns:
            deletes.extend(
                self._store.quads_for_pattern(
                    pattern.subject, pattern.predicate, to_store(pattern.object), pattern.graph
                )
            )
        text: str | None = None
        if self.remote is not None:
            self._trace("update", f"REMOTE {len(deletes)} deletions, {len(inserts)} inserts", {})
            apply: Callable[[], None] = functools.partial(
                self.remote.commit, tx.cleared, deletes, inserts
            )
        elif not (deletes or tx.cleared):
            self._trace("extend", f"INSERT {len(inserts)} quads", {})
            apply = functools.partial(self._store.extend, inserts)
        else:
            text = update_text(tx.cleared, deletes, inserts)
            self._trace("update", text, {})
            apply = functools.partial(self._store.update, text)

        def write() -> None:
            try:
                apply()
            except (OSError, SyntaxError, ValueError) as error:
                raise TransactionError(
                    f"transaction not applied, store unchanged: {error}"
                ) from error
            if self._commit_log is not None:  # recorded before the generation says it is there
                if self.remote is not None:
                    self._commit_log.unrecorded(self._generation + 1)
                elif text is None:
                    self._commit_log.record(self._generation + 1, inserts=inserts)
                else:
                    self._commit_log.record(self._generation + 1, update=text)
            self._generation += 1
            log.debug("committed %d deletions, %d insertions", len(deletes), len(inserts))

        return write

    # Bulk writes -------------------------------------------------------------------------------

    def fill_graph(self, graph: NamedNode, ntriples: bytes | Iterable[bytes]) -> None:
        """Write an N-Triples document into the empty graph ``graph``: all of it, or nothing.

        ``ntriples`` is the document, or its pieces as an iterable of bytes (each ending at a
        line end): the loader then ingests them while the iterable produces the next ones (a
        reasoner writes its closure while it derives it), through a pipe, in a thread that holds
        no GIL. An exception from the iterable leaves the graph empty and propagates.

        For large writes into a new graph (a REASON's closure of 100k triples): Oxigraph's bulk
        loader writes sorted files and ingests them, about twice as fast on disk as a
        transaction, but it is not transactional, so the load is bracketed by a marker:

        1. a marker naming ``graph`` is committed in the ``bulk-writes`` graph;
        2. the triples are bulk loaded into ``graph``;
        3. the marker is removed (one transaction).

        If step 2 or 3 fails, ``graph`` is cleared and the marker removed before the error is
        raised; if the process dies in between, opening the store clears it
        (:meth:`recover_bulk_writes`). Either way ``graph`` ends up as it was (empty) or holding
        every triple. The write lock is held throughout, so no transaction interleaves; the store's
        :attr:`generation` advances by one.

        Raises ``TypeError`` if ``graph`` is not a NamedNode, ``ValueError`` if it holds
        triples, and :class:`TransactionError` (the graph left empty) if the load fails, for
        instance on malformed N-Triples.

        >>> from ontologies.vocab import MEMORY
        >>> store = Store()
        >>> store.fill_graph(MEMORY, b'<http://ex.org/a> <http://ex.org/p> "1" .\\n')
        >>> len(store), list(store.quads(graph=BULK_WRITES))
        (1, [])
        """
        if not isinstance(graph, NamedNode):
            raise TypeError(f"graph must be a NamedNode naming an Engram graph, got {graph!r}")
        marker = Quad(graph, RDF_TYPE, UNFINISHED_BULK_WRITE, BULK_WRITES)
        with self._write_lock:
            if next(iter(self._store.quads_for_pattern(None, None, None, graph)), None):
                raise ValueError(f"graph: {graph} holds triples, expected an empty graph")
            size = f"{len(ntriples)} bytes" if isinstance(ntriples, bytes) else "streamed"
            self._trace("extend", f"BULK LOAD INTO {graph} ({size})", {})
            try:
                self._store.extend([marker])
            except OSError as error:
                raise TransactionError(
                    f"bulk write not started, store unchanged: {error}"
                ) from error
            try:
                if isinstance(ntriples, bytes) or self.remote is not None:
                    data = ntriples if isinstance(ntriples, bytes) else b"".join(ntriples)
                    self._store.bulk_load(
                        ntriples_to_store(data),
                        format=pyoxigraph.RdfFormat.N_TRIPLES,
                        to_graph=graph,
                    )
                else:
                    self._bulk_load_streamed(graph, map(ntriples_to_store, ntriples))
                self._end_bulk_write(marker)
            except BaseException as error:
                self._undo_bulk_write(marker)
                if isinstance(error, OSError | SyntaxError | ValueError):
                    raise TransactionError(
                        f"bulk write into {graph} not applied, graph left empty: {error}"
                    ) from error
                raise
            finally:
                self._unrecorded_write()
        log.debug("bulk loaded N-Triples into %s", graph)

    def _bulk_load_streamed(self, graph: NamedNode, pieces: Iterable[bytes]) -> None:
        """Bulk load N-Triples pieces into ``graph`` as they come: Oxigraph reads them from a
        pipe by path in a thread of its own (no GIL), while this thread writes them."""
        read_end, write_end = os.pipe()
        with contextlib.suppress(OSError):  # a larger buffer: fewer waits (Linux only)
            fcntl.fcntl(write_end, getattr(fcntl, "F_SETPIPE_SZ", 1031), 1 << 20)
        failure: list[BaseException] = []

        store = self._store
        assert isinstance(store, pyoxigraph.Store)  # a server's store is given whole bytes

        def load() -> None:
            try:
                store.bulk_load(
                    path=f"/dev/fd/{read_end}",
                    format=pyoxigraph.RdfFormat.N_TRIPLES,
                    to_graph=graph,
                )
            except BaseException as error:
                failure.append(error)

        loader = threading.Thread(target=load, name="engram-bulk-load")
        loader.start()
        os.set_blocking(write_end, False)  # so that a loader that failed cannot block us
        try:
            for piece in pieces:
                view = memoryview(piece)
                while view and loader.is_alive():
                    try:
                        view = view[os.write(write_end, view) :]
                    except BlockingIOError:
                        select.select([], [write_end], [], 0.1)
                if not loader.is_alive():
                    break  # it stopped reading: its error is raised below
        except BrokenPipeError:
            pass  # likewise
        finally:
            os.close(write_end)
            loader.join()
            os.close(read_end)
        if failure:
            raise failure[0]

    def _end_bulk_write(self, marker: Quad) -> None:
        self._store.remove(marker)

    def _undo_bulk_write(self, marker: Quad) -> None:
        """Clear a half-written graph and its marker in one update (the marker stays if this
        fails, for :meth:`recover_bulk_writes`)."""
        graph, kind = marker.subject, UNFINISHED_BULK_WRITE
        self._store.update(
            f"CLEAR SILENT GRAPH {graph} ;\n"
            f"DELETE DATA {{ GRAPH {BULK_WRITES} {{ {graph} {RDF_TYPE} {kind} }} }}"
        )

    def recover_bulk_writes(self) -> list[NamedNode]:
        """Clear every graph a :meth:`fill_graph` left half-written (the process died during it).

        Opening an on-disk store calls it, before anything reads the store. Returns the graphs
        cleared (none after a clean shutdown).
        """
        with self._write_lock:
            markers = list(self._store.quads_for_pattern(None, RDF_TYPE, None, BULK_WRITES))
            cleared = []
            for marker in markers:
                if isinstance(marker.subject, NamedNode):
                    log.warning("clearing %s: a bulk write into it did not finish", marker.subject)
                    self._undo_bulk_write(marker)
                    cleared.append(marker.subject)
                else:
                    self._store.remove(marker)
            if markers:
                self._unrecorded_write()
        return cleared

    # Maintenance -------------------------------------------------------------------------------

    def backup(self, target: str | os.PathLike[str]) -> Path:
        """Write a consistent copy of an on-disk store to the new directory ``target``.

        On the same file system the copy is made of hard links and is cheap. Raises
        ``FileExistsError`` if ``target`` exists and ``StoreError`` for an in-memory store.
        """
        self.settle_reads()
        if self.remote is not None:
            self.remote.backup(str(target))
        if self.path is None:
            raise StoreError("an in-memory store cannot be backed up; open one on disk")
        target = Path(target)
        if target.exists():
            raise FileExistsError(f"backup target {target} already exists")
        target.parent.mkdir(parents=True, exist_ok=True)
        with self._flush_lock:
            self._store.backup(str(target))
        return target

    def flush(self) -> None:
        """Make sure every committed write is on disk (after any flush under way, from any
        thread)."""
        with self._flush_lock:
            self._store.flush()

    def flush_in_background(self) -> None:
        """Start :meth:`flush` in a thread of its own and return at once (an embedded store on
        disk only; nothing if one is still running). For after a large transaction: the writes
        that follow then go to an empty memtable, as in a store just flushed, instead of one the
        large write filled, where each costs more. A failure is logged: what was committed is in
        the write-ahead log either way. :meth:`close` waits for it."""
        if self.path is None or isinstance(self._store, _ClosedStore):
            return
        if self._flusher is not None and self._flusher.is_alive():
            return
        store, path, lock = self._store, self.path, self._flush_lock  # not self: see __del__

        def flush() -> None:
            try:
                with lock:
                    store.flush()
            except OSError as error:
                log.warning("the store at %s could not be flushed: %s", path, error)

        self._flusher = threading.Thread(target=flush, name="engram-flush", daemon=True)
        self._flusher.start()

    def __del__(self) -> None:
        # a background flush holds the underlying store, whose directory stays locked until it
        # ends: wait for it, so that the directory is free once this object is gone
        flusher = getattr(self, "_flusher", None)
        if flusher is not None:
            flusher.join()

    def close(self) -> None:
        """Flush and let go of the store: an embedded store's directory is free for another
        process at once, whoever still holds this object; any later call raises StoreError."""
        if isinstance(self._store, _ClosedStore):
            return
        if self._flusher is not None:
            self._flusher.join()
        self.flush()
        self._store = _ClosedStore(self.path)  # type: ignore[assignment]

    def __len__(self) -> int:
        return len(self._store)


class _ClosedStore:
    """What a closed :class:`Store` holds instead of the store it let go of."""

    def __init__(self, path: Path | None) -> None:
        self.path = path

    def __getattr__(self, name: str) -> Any:
        raise StoreError(f"the store at {self.path} was closed")

    def __len__(self) -> int:
        raise StoreError(f"the store at {self.path} was closed")


def update_text(cleared: list[NamedNode], deletes: list[Quad], inserts: list[Quad]) -> str:
    """One SPARQL update; terms are written by pyoxigraph's own serialisation, never by hand."""
    operations = [f"CLEAR SILENT GRAPH {graph}" for graph in cleared]
    if deletes:
        operations.append(f"DELETE DATA {{ {_quad_block(deletes)} }}")
    if inserts:
        operations.append(f"INSERT DATA {{ {_quad_block(inserts)} }}")
    return " ;\n".join(operations)


def _quad_block(quads: list[Quad]) -> str:
    """``GRAPH <g> { s p o . ... }`` per graph (one string per triple from pyoxigraph: the
    update texts of a sleep pass hold tens of thousands of quads)."""
    by_graph: dict[NamedNode, list[str]] = {}
    for quad in quads:
        by_graph.setdefault(quad.graph_name, []).append(str(quad.triple))  # type: ignore[arg-type]
    return "\n".join(
        "GRAPH {} {{ {} }}".format(graph, " .\n".join(triples))
        for graph, triples in by_graph.items()
    )
