"""A memory on a shared SPARQL server: the remote backend of :class:`kg.Store`.

:class:`RemoteDataset` answers what :class:`kg.Store` asks of ``pyoxigraph.Store`` (queries, quad
patterns, atomic writes, graph dumps and loads) over SPARQL 1.1 Query, Update and the Graph
Store Protocol, for one robot's memory (:class:`kg.namespace.Namespace`):

- Queries name their dataset explicitly (``default-graph-uri``, ``named-graph-uri``): the
  memory's own graphs, never a union of everything on the server.
- An Engram transaction is one update request, which also moves the memory's revision from n to
  n+1 and adds journal entry n+1 naming the subjects it touched (or "everything", for a cleared
  graph or a very large write), and drops the entry that falls out of the journal.
- A write that failed leaves the dataset *unsettled*: before the next write (and from the lease
  renewer's thread) it reads the revision back, which tells whether the failed write applied,
  and tells its listeners to rebuild what they keep in memory from the store.

>>> RemoteDataset.__name__
'RemoteDataset'
"""

import datetime as dt
import logging
import threading
from collections.abc import Callable, Iterable, Iterator, Sequence
from dataclasses import dataclass
from typing import Any

import pyoxigraph
from pyoxigraph import (
    Literal,
    NamedNode,
    Quad,
    QueryBoolean,
    QueryResultsFormat,
    QuerySolutions,
    QueryTriples,
    RdfFormat,
)

import sparql
from kg.errors import ReadOnlyStoreError, StoreError, StoreUnavailableError
from kg.http import SparqlServer, WriteOutcomeUnknownError
from kg.namespace import Namespace
from kg.sparql_text import bind_values
from kg.store import update_text
from ontologies.vocab import (
    COMMITTED_AT,
    JOURNAL_ENTRY,
    RDF_TYPE,
    REVISION,
    SKOLEM_PREFIX,
    TOUCHED,
    TOUCHED_EVERYTHING,
    XSD_BOOLEAN,
    XSD_DATETIME,
    XSD_INTEGER,
)

__all__ = ["Change", "RemoteDataset"]

log = logging.getLogger(__name__)

JOURNAL_LENGTH = 1000
"""Journal entries kept; a follower further behind than this rebuilds everything."""
TOUCHED_LIMIT = 5000
"""A transaction touching more subjects than this is journaled as touching everything. Listing
them costs the writer one journal triple per subject, no more than the transaction changed
itself; a follower reloads a listed subject by one index lookup, while "everything" makes it
rebuild its whole scene memory index (seconds at 10,000 classes). A new class linked above
hundreds of existing ones touches them all."""


@dataclass(frozen=True)
class Change:
    """What moved a memory to ``revision``: the subjects touched, or None for "everything"."""

    revision: int
    touched: frozenset[NamedNode] | None


Listener = Callable[[Change], None]


class RemoteDataset:
    """One robot's memory on a SPARQL server, with the methods :class:`kg.Store` uses.

    ``read_only`` datasets refuse writes with :class:`ReadOnlyStoreError`; ``guard`` (the
    writer's lease) is called before every write and raises if the lease is not held.
    """

    def __init__(
        self,
        server: SparqlServer,
        namespace: Namespace,
        *,
        read_only: bool = False,
        journal_length: int = JOURNAL_LENGTH,
    ) -> None:
        self.server = server
        self.namespace = namespace
        self.read_only = read_only
        self.journal_length = journal_length
        self.guard: Callable[[], None] | None = None
        self._listeners: list[Listener] = []
        self._graphs: set[str] | None = None
        self._unsettled = False
        self._pending: int | None = None
        self._settling = threading.Lock()
        self.revision = self.read_revision()

    # Listeners -----------------------------------------------------------------------------------

    def listen(self, listener: Listener) -> None:
        """Call ``listener`` with each change this object learns of after a failure (writer) or
        from the journal (follower), after the store holds it."""
        self._listeners.append(listener)

    def notify(self, change: Change) -> None:
        self._graphs = None if change.touched is None else self._graphs
        for listener in list(self._listeners):
            listener(change)

    # Reads ---------------------------------------------------------------------------------------

    def graphs(self) -> list[str]:
        """The memory's graphs on the server (remote IRIs), listed once and kept up to date by
        this object's writes; a follower lists them again at each change."""
        if self._graphs is None:
            text = bind_values(
                sparql.load("remote_graphs"), {"prefix": Literal(self.namespace.graph_prefix)}
            )
            rows = self.select_raw(text, default_graphs=[], named_graphs=None)
            self._graphs = {row["g"].value for row in rows}
        return sorted(self._graphs)

    def named_graphs(self) -> list[NamedNode]:
        """The memory's graphs under Engram's own names (as :meth:`kg.Store.named_graphs`)."""
        return [NamedNode(self.namespace.local_iri(g)) for g in self.graphs()]

    def forget_graphs(self) -> None:
        self._graphs = None

    def read_revision(self) -> int:
        text = bind_values(
            sparql.load("remote_revision"),
            {"control": self.namespace.control, "memory": self.namespace.node},
        )
        rows = self.select_raw(
            text,
            default_graphs=[self.namespace.control.value],
            named_graphs=[self.namespace.control.value],
        )
        return max((int(row["revision"].value) for row in rows), default=0)

    def query(
        self,
        text: str,
        *,
        use_default_graph_as_union: bool = False,
        default_graph: Sequence[NamedNode] | None = None,
        named_graphs: Sequence[NamedNode] | None = None,
        also: Sequence[str] = (),
    ) -> QuerySolutions | QueryBoolean | QueryTriples:
        """Run ``text`` over the memory's graphs (``use_default_graph_as_union``) or the chosen
        ones; answers come back with Engram's own graph names. ``also`` adds other graphs of the
        server (by their server names: other robots' memories a fleet view follows) to the
        union."""
        if use_default_graph_as_union or default_graph is None:
            default = named = [*self.graphs(), *also]
        else:
            default = [self.namespace.remote_graph(g).value for g in default_graph]
            named = [self.namespace.remote_graph(g).value for g in named_graphs or ()]
        return self._query_remote(self.namespace.rewrite_text(text), default, named)

    def _query_remote(
        self, text: str, default: Sequence[str], named: Sequence[str] | None
    ) -> QuerySolutions | QueryBoolean | QueryTriples:
        # An empty list would mean "the server's whole dataset": name a graph nobody writes.
        nothing = [self.namespace.prefix + "nothing"]
        response = self.server.query(
            text,
            default_graphs=list(default) or nothing,
            named_graphs=(list(named) or nothing) if named is not None else nothing,
        )
        media = response.headers.get("content-type", "").split(";")[0].strip()
        if media == "application/n-triples":
            return _as_query_triples(self.namespace.restore_text(response.text))
        data = self.namespace.restore_results_xml(response.content)
        return pyoxigraph.parse_query_results(data, QueryResultsFormat.XML)

    def select_raw(
        self, text: str, *, default_graphs: Sequence[str], named_graphs: Sequence[str] | None
    ) -> list[dict[str, Any]]:
        """Rows of a SELECT in server terms (no renaming); ``named_graphs=None`` lets the query
        see every graph on the server (only to list this memory's own)."""
        response = self.server.query(
            text, default_graphs=default_graphs, named_graphs=named_graphs or []
        )
        result: Any = pyoxigraph.parse_query_results(response.content, QueryResultsFormat.XML)
        names = [v.value for v in result.variables]
        return [{n: term for n in names if (term := row[n]) is not None} for row in result]

    def quads_for_pattern(
        self,
        subject: NamedNode | None,
        predicate: NamedNode | None,
        obj: NamedNode | Literal | None,
        graph: NamedNode | None = None,
    ) -> Iterator[Quad]:
        bound = {
            name: term
            for name, term in (("s", subject), ("p", predicate), ("o", obj), ("g", graph))
            if term is not None
        }
        text = self.namespace.rewrite_text(bind_values(sparql.load("remote_quads"), bound))
        named = [self.namespace.remote_graph(graph).value] if graph is not None else self.graphs()
        result = self._query_remote(text, (), named)
        assert isinstance(result, QuerySolutions)
        quads = []
        for row in result:
            g = row["g"]
            quads.append(Quad(row["s"], row["p"], row["o"], g))
        return iter(quads)

    def dump(self, *, format: RdfFormat, from_graph: NamedNode) -> bytes:
        """The N-Triples of one graph (Graph Store Protocol GET); empty if it does not exist."""
        if format != RdfFormat.N_TRIPLES:
            raise ValueError(f"format: got {format}, expected N-Triples")
        data = self.server.get_graph(self.namespace.remote_graph(from_graph).value)
        return self.namespace.restore_text(data.decode()).encode() if data else b""

    def __len__(self) -> int:
        result = self.query(
            "SELECT (COUNT(*) AS ?n) WHERE { GRAPH ?g { ?s ?p ?o } }",
            use_default_graph_as_union=True,
        )
        assert isinstance(result, QuerySolutions)
        return sum(int(row["n"].value) for row in result)

    # Writes --------------------------------------------------------------------------------------

    def commit(
        self, cleared: Sequence[NamedNode], deletes: Sequence[Quad], inserts: Sequence[Quad]
    ) -> None:
        """Apply one transaction as one update request, with its revision and journal entry.

        Raises :class:`ReadOnlyStoreError` on a follower, :class:`StoreUnavailableError` when
        the server cannot be reached (or went away during the write: whether it applied is then
        settled by the revision before the next write), :class:`kg.errors.TransactionError` when
        the server refused it. The lease guard's errors propagate.
        """
        self._require_writer()
        touched = _touched(cleared, deletes, inserts)
        ns = self.namespace
        revision = self.revision + 1
        data = update_text(
            [ns.remote_graph(g) for g in cleared],
            [ns.remote_quad(q) for q in deletes],
            [ns.remote_quad(q) for q in inserts],
        )
        text = " ;\n".join(part for part in (data, self._journal_text(revision, touched)) if part)
        try:
            self.server.update(text)
        except WriteOutcomeUnknownError:
            self._unsettled, self._pending = True, revision
            raise
        except StoreError:
            self._unsettled, self._pending = True, None
            raise
        self.revision = revision
        if self._graphs is not None:
            self._graphs.update(ns.remote_iri(str(q.graph_name.value)) for q in inserts)  # type: ignore[union-attr]

    def _journal_text(self, revision: int, touched: frozenset[NamedNode] | None) -> str:
        ns, entry = self.namespace, self.namespace.entry(revision)
        now = Literal(dt.datetime.now(dt.UTC).isoformat(), datatype=XSD_DATETIME)
        quads = [
            Quad(ns.node, REVISION, _integer(revision), ns.control),
            Quad(entry, RDF_TYPE, JOURNAL_ENTRY, ns.control),
            Quad(entry, REVISION, _integer(revision), ns.control),
            Quad(entry, COMMITTED_AT, now, ns.control),
        ]
        if touched is None:
            quads.append(
                Quad(entry, TOUCHED_EVERYTHING, Literal("true", datatype=XSD_BOOLEAN), ns.control)
            )
        else:
            quads.extend(
                Quad(entry, TOUCHED, ns.remote(s), ns.control) for s in sorted(touched, key=str)
            )
        old = [Quad(ns.node, REVISION, _integer(revision - 1), ns.control)] if revision > 1 else []
        parts = [update_text([], old, quads)]
        if revision > self.journal_length:
            trim = {"control": ns.control, "entry": ns.entry(revision - self.journal_length)}
            parts.append(bind_values(sparql.load("remote_journal_trim"), trim))
        return " ;\n".join(parts)

    def extend(self, quads: Iterable[Quad]) -> None:
        self.commit([], [], list(quads))

    def remove(self, quad: Quad) -> None:
        self.commit([], [quad], [])

    def update(self, text: str) -> None:
        """A raw update (clearing a half-written graph): journaled as touching everything."""
        self._require_writer()
        revision = self.revision + 1
        full = self.namespace.rewrite_text(text) + " ;\n" + self._journal_text(revision, None)
        try:
            self.server.update(full)
        except WriteOutcomeUnknownError:
            self._unsettled, self._pending = True, revision
            raise
        except StoreError:
            self._unsettled, self._pending = True, None
            raise
        self.revision = revision

    def bulk_load(self, data: bytes, *, format: RdfFormat, to_graph: NamedNode) -> None:
        """Add N-Triples to a graph by the Graph Store Protocol (bracketed by
        :meth:`kg.Store.fill_graph`'s marker, whose removal is the journaled transaction)."""
        self._require_writer()
        if format != RdfFormat.N_TRIPLES:
            raise ValueError(f"format: got {format}, expected N-Triples")
        graph = self.namespace.remote_graph(to_graph).value
        body = self.namespace.rewrite_text(data.decode()).encode()
        pyoxigraph.parse(body, format=RdfFormat.N_TRIPLES)  # refuse bad input before sending
        self.server.post_graph(graph, body)
        if self._graphs is not None:
            self._graphs.add(graph)

    def flush(self) -> None:
        """Nothing to do: the server made each acknowledged write durable."""

    def backup(self, target: str) -> None:
        raise StoreError(
            "a memory on a SPARQL server is backed up by the server (`oxigraph backup`), "
            "not by Engram"
        )

    # Failures ------------------------------------------------------------------------------------

    def settle(self) -> Change | None:
        """After a failed write, read the revision back and tell the listeners to rebuild.

        Returns the change (None if nothing was unsettled). Raises
        :class:`StoreUnavailableError` while the server is still away, or while another thread
        is settling.
        """
        if not self._unsettled:
            return None
        if not self._settling.acquire(blocking=False):
            raise StoreUnavailableError("catching up with the SPARQL server; retry shortly")
        try:
            if not self._unsettled:
                return None
            revision = self.read_revision()
            if self._pending is not None and revision == self._pending:
                log.info("the write that failed at revision %d had applied", revision)
            self.revision = revision
            self._unsettled, self._pending = False, None
            change = Change(revision, None)
            self.notify(change)
            return change
        finally:
            self._settling.release()

    def _require_writer(self) -> None:
        if self.read_only:
            raise ReadOnlyStoreError(
                f"this Engram follows memory {self.namespace.name!r} read-only; "
                "write through the Engram that holds its lease"
            )
        if self._unsettled:  # kg.Store.transaction settles before it takes the write lock
            raise StoreUnavailableError("catching up with the SPARQL server; retry shortly")
        if self.guard is not None:
            self.guard()


def _integer(value: int) -> Literal:
    return Literal(str(value), datatype=XSD_INTEGER)


def _touched(
    cleared: Sequence[NamedNode], deletes: Sequence[Quad], inserts: Sequence[Quad]
) -> frozenset[NamedNode] | None:
    if cleared:
        return None
    # a skolem node (a class's definition, a list cell) is written with the resource that links
    # to it, which the journal names: listing it too would only lengthen the journal
    subjects = {
        q.subject
        for q in (*deletes, *inserts)
        if isinstance(q.subject, NamedNode) and not q.subject.value.startswith(SKOLEM_PREFIX)
    }
    if len(subjects) > TOUCHED_LIMIT:
        return None
    return frozenset(subjects)


def _as_query_triples(ntriples: str) -> QueryTriples:
    """A CONSTRUCT answer as pyoxigraph's own result type (parsed into a scratch store)."""
    scratch = pyoxigraph.Store()
    scratch.load(ntriples.encode(), format=RdfFormat.N_TRIPLES)
    result = scratch.query("CONSTRUCT { ?s ?p ?o } WHERE { ?s ?p ?o }")
    assert isinstance(result, QueryTriples)
    return result
