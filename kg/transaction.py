"""Collect deletions and insertions, then apply them as one atomic write.

A :class:`Transaction` only records what the code wants changed; nothing touches the store until
:meth:`kg.store.Store.transaction` commits it, as one SPARQL update (or one ``extend`` when it only
inserts), both of which pyoxigraph applies all-or-nothing. An exception before the commit leaves
the store untouched.
"""

import os
from collections.abc import Iterator
from dataclasses import dataclass, field
from pathlib import Path
from typing import Protocol

from pyoxigraph import BlankNode, Literal, NamedNode, Quad, RdfFormat, parse

from kg.skolem import Skolemiser

__all__ = ["Object", "Pattern", "QuadReader", "Subject", "Transaction"]

Subject = NamedNode | BlankNode
Object = NamedNode | BlankNode | Literal


class QuadReader(Protocol):
    """Anything that reads quads by pattern as :meth:`kg.store.Store.quads` does."""

    def quads(
        self,
        subject: NamedNode | None = None,
        predicate: NamedNode | None = None,
        obj: NamedNode | Literal | None = None,
        graph: NamedNode | None = None,
    ) -> Iterator[Quad]: ...


@dataclass(frozen=True)
class Pattern:
    """A quad pattern whose matches are deleted at commit time (``None`` matches anything)."""

    subject: NamedNode | None
    predicate: NamedNode | None
    object: NamedNode | Literal | None
    graph: NamedNode


@dataclass
class Transaction:
    """The pending changes of one atomic write.

    Deletions apply before insertions, so deleting and inserting the same quad keeps it.
    Blank nodes are replaced with skolem IRIs, one per distinct blank node in the transaction.
    Every quad must be in a named graph: Engram keeps nothing in the default graph.
    """

    inserts: list[Quad] = field(default_factory=list)
    deletes: list[Quad] = field(default_factory=list)
    patterns: list[Pattern] = field(default_factory=list)
    cleared: list[NamedNode] = field(default_factory=list)
    _skolem: Skolemiser = field(default_factory=Skolemiser, repr=False)

    def insert(self, subject: Subject, predicate: NamedNode, obj: Object, graph: NamedNode) -> None:
        """Add one triple to ``graph``."""
        self.inserts.append(self._quad(subject, predicate, obj, graph))

    def delete(self, subject: Subject, predicate: NamedNode, obj: Object, graph: NamedNode) -> None:
        """Remove one triple from ``graph`` (no error if it is absent)."""
        self.deletes.append(self._quad(subject, predicate, obj, graph))

    def delete_matching(
        self,
        subject: NamedNode | None = None,
        predicate: NamedNode | None = None,
        obj: NamedNode | Literal | None = None,
        *,
        graph: NamedNode,
    ) -> None:
        """Remove every triple of ``graph`` matching the pattern, as the store is at commit."""
        _require_graph(graph)
        self.patterns.append(Pattern(subject, predicate, obj, graph))

    def clear_graph(self, graph: NamedNode) -> None:
        """Remove every triple of ``graph``."""
        _require_graph(graph)
        self.cleared.append(graph)

    def load(
        self,
        source: str | bytes | os.PathLike[str],
        *,
        format: RdfFormat,
        graph: NamedNode,
        base_iri: str | None = None,
    ) -> int:
        """Parse an RDF document into ``graph`` and return the number of triples it held.

        ``source`` is the document itself (``str`` or ``bytes``) or a path to it. Raises
        ``SyntaxError`` with the parser's position if the document is malformed; nothing is then
        recorded.
        """
        _require_graph(graph)
        if isinstance(source, os.PathLike):
            quads = parse(path=Path(source), format=format, base_iri=base_iri)
        else:
            quads = parse(source, format=format, base_iri=base_iri)
        parsed = [self._quad(q.subject, q.predicate, q.object, graph) for q in quads]
        self.inserts.extend(parsed)
        return len(parsed)

    @property
    def is_empty(self) -> bool:
        return not (self.inserts or self.deletes or self.patterns or self.cleared)

    def _quad(self, subject: Subject, predicate: NamedNode, obj: Object, graph: NamedNode) -> Quad:
        _require_graph(graph)
        if not isinstance(predicate, NamedNode):
            raise TypeError(f"predicate must be a NamedNode, got {predicate!r}")
        if isinstance(subject, BlankNode) or isinstance(obj, BlankNode):
            return Quad(self._skolem.term(subject), predicate, self._skolem.term(obj), graph)
        return Quad(subject, predicate, obj, graph)


def _require_graph(graph: object) -> None:
    if not isinstance(graph, NamedNode):
        raise TypeError(f"graph must be a NamedNode naming an Engram graph, got {graph!r}")
