"""The one place that touches ``pyoxigraph.Store``.

>>> from ontologies.vocab import MEMORY, engram, RDFS_LABEL
>>> from pyoxigraph import Literal
>>> store = Store()                      # in memory; Store(path) opens or creates a directory
>>> with store.transaction() as tx:
...     tx.insert(engram("Scene-1"), RDFS_LABEL, Literal("a scene"), MEMORY)
>>> store.select("graph_sizes")[0]["triples"].value
'1'
"""

import logging
import os
import threading
from collections.abc import Callable, Iterator, Mapping, Sequence
from contextlib import contextmanager
from pathlib import Path
from typing import Any

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
from kg.errors import (
    QueryRefusedError,
    QuerySyntaxError,
    StoreError,
    StoreLockedError,
    TransactionError,
)
from kg.sparql_text import bind_values, mentions_keyword
from kg.transaction import Transaction

__all__ = ["Binding", "Store", "Tracer"]

log = logging.getLogger(__name__)

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
    """

    def __init__(self, path: str | os.PathLike[str] | None = None, *, tracer: Tracer | None = None):
        self.path = Path(path) if path is not None else None
        try:
            if self.path is not None:
                self.path.mkdir(parents=True, exist_ok=True)
            self._store = pyoxigraph.Store(str(self.path)) if self.path else pyoxigraph.Store()
        except OSError as error:
            if "lock" in str(error).lower():
                raise StoreLockedError(
                    f"the store at {self.path} is open in another process "
                    "(is `engram serve` running?); stop it or talk to it over HTTP"
                ) from error
            raise StoreError(f"cannot open the store at {self.path}: {error}") from error
        self._write_lock = threading.Lock()
        self._tracers: list[Tracer] = [tracer] if tracer else []
        self._generation = 0

    @property
    def generation(self) -> int:
        """How many transactions this object has committed; a cheap "has anything changed" test."""
        return self._generation

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

    def _select(
        self, text: str, bindings: Mapping[str, Binding], name: str = "query"
    ) -> list[dict[str, Binding]]:
        result = self._query(text, bindings)
        if not isinstance(result, QuerySolutions):
            raise TypeError(f"query {name!r} is not a SELECT query")
        names = [variable.value for variable in result.variables]
        return [{n: term for n in names if (term := row[n]) is not None} for row in result]

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
        return list(result)

    def _query(self, text: str, bindings: Mapping[str, Binding]) -> Any:
        text = bind_values(text, bindings)
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
        """The stored quads matching a pattern (``None`` matches anything)."""
        return self._store.quads_for_pattern(subject, predicate, obj, graph)

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
        self._trace("query", f"DUMP GRAPH {graph} AS N-Triples", {})
        return self._store.dump(format=pyoxigraph.RdfFormat.N_TRIPLES, from_graph=graph) or b""

    # Writes ------------------------------------------------------------------------------------

    @contextmanager
    def transaction(self) -> Iterator[Transaction]:
        """Collect changes in the ``with`` block and apply them atomically when it ends.

        If the block raises, nothing is written. If the write itself fails,
        :class:`TransactionError` is raised and the store is unchanged.
        """
        with self._write_lock:
            tx = Transaction()
            yield tx
            self._commit(tx)

    def _commit(self, tx: Transaction) -> None:
        if tx.is_empty:
            return
        deletes = list(tx.deletes)
        for pattern in tx.patterns:
            deletes.extend(
                self._store.quads_for_pattern(
                    pattern.subject, pattern.predicate, pattern.object, pattern.graph
                )
            )
        try:
            if not (deletes or tx.cleared):
                self._trace("extend", f"INSERT {len(tx.inserts)} quads", {})
                self._store.extend(tx.inserts)
            else:
                text = _update_text(tx.cleared, deletes, tx.inserts)
                self._trace("update", text, {})
                self._store.update(text)
        except (OSError, SyntaxError, ValueError) as error:
            raise TransactionError(f"transaction not applied, store unchanged: {error}") from error
        self._generation += 1
        log.debug("committed %d deletions, %d insertions", len(deletes), len(tx.inserts))

    # Maintenance -------------------------------------------------------------------------------

    def backup(self, target: str | os.PathLike[str]) -> Path:
        """Write a consistent copy of an on-disk store to the new directory ``target``.

        On the same file system the copy is made of hard links and is cheap. Raises
        ``FileExistsError`` if ``target`` exists and ``StoreError`` for an in-memory store.
        """
        if self.path is None:
            raise StoreError("an in-memory store cannot be backed up; open one on disk")
        target = Path(target)
        if target.exists():
            raise FileExistsError(f"backup target {target} already exists")
        target.parent.mkdir(parents=True, exist_ok=True)
        self._store.backup(str(target))
        return target

    def flush(self) -> None:
        """Make sure every committed write is on disk."""
        self._store.flush()

    def __len__(self) -> int:
        return len(self._store)


def _update_text(cleared: list[NamedNode], deletes: list[Quad], inserts: list[Quad]) -> str:
    """One SPARQL update; terms are written by pyoxigraph's own serialisation, never by hand."""
    operations = [f"CLEAR SILENT GRAPH {graph}" for graph in cleared]
    if deletes:
        operations.append(f"DELETE DATA {{ {_quad_block(deletes)} }}")
    if inserts:
        operations.append(f"INSERT DATA {{ {_quad_block(inserts)} }}")
    return " ;\n".join(operations)


def _quad_block(quads: list[Quad]) -> str:
    return "\n".join(
        f"GRAPH {q.graph_name} {{ {q.subject} {q.predicate} {q.object} }}" for q in quads
    )
