"""One robot's memory on a shared SPARQL server: its graph names there, and the renaming.

Engram's code names its graphs ``https://w3id.org/engram/graph/<g>`` (``ontologies.vocab``). On
a server holding several robots' memories, robot ``r``'s graph ``<g>`` is stored as
``https://w3id.org/engram/memory/r/graph/<g>``. The renaming is a bijection on IRIs applied at
the boundary: IRIs (in query text, bound terms, quads and results) that start with one prefix
are rewritten to start with the other, and nothing else changes, so a query means the same thing
on either side. Only IRI tokens are rewritten, never strings or comments.

>>> ns = Namespace("robot-a")
>>> ns.remote_iri("https://w3id.org/engram/graph/memory")
'https://w3id.org/engram/memory/robot-a/graph/memory'
>>> ns.rewrite_text('GRAPH <https://w3id.org/engram/graph/m> { ?s ?p "<.../graph/m>" }')
'GRAPH <https://w3id.org/engram/memory/robot-a/graph/m> { ?s ?p "<.../graph/m>" }'
"""

import re
from collections.abc import Callable
from dataclasses import dataclass, field

from pyoxigraph import BlankNode, Literal, NamedNode, Quad, Triple

from ontologies.vocab import GRAPH_NS, MEMORY_NS

__all__ = ["Namespace"]

_NAME = re.compile(r"[A-Za-z0-9][A-Za-z0-9_-]{0,63}")
_TOKENS = re.compile(
    r'"""(?:[^"\\]|\\.|"(?!""))*"""'
    r"|'''(?:[^'\\]|\\.|'(?!''))*'''"
    r'|"(?:[^"\\\n]|\\.)*"'
    r"|'(?:[^'\\\n]|\\.)*'"
    r"|#[^\n]*"
    r"|<([^<>\"{}|^`\\\s]*)>"
)
"""Strings, comments and IRI references of SPARQL or N-Triples text; group 1 is an IRI's text."""

Term = NamedNode | BlankNode | Literal | Triple


@dataclass(frozen=True)
class Namespace:
    """The graph names of memory ``name`` on a shared server.

    Raises ``ValueError`` if ``name`` is not 1 to 64 letters, digits, ``-`` or ``_`` starting with a
    letter or digit.
    """

    name: str
    prefix: str = field(init=False)
    graph_prefix: str = field(init=False)

    def __post_init__(self) -> None:
        if not isinstance(self.name, str) or not _NAME.fullmatch(self.name):
            raise ValueError(
                f"memory: got {self.name!r}, expected 1-64 letters, digits, '-' or '_' "
                "starting with a letter or digit"
            )
        object.__setattr__(self, "prefix", f"{MEMORY_NS}{self.name}/")
        object.__setattr__(self, "graph_prefix", f"{MEMORY_NS}{self.name}/graph/")

    @property
    def node(self) -> NamedNode:
        """The memory itself: the subject of its revision and its writer's lease."""
        return NamedNode(self.prefix)

    @property
    def control(self) -> NamedNode:
        """The graph holding the memory's revision, change journal and lease."""
        return NamedNode(self.prefix + "control")

    def entry(self, revision: int) -> NamedNode:
        """The journal entry of the transaction that made ``revision``."""
        return NamedNode(f"{self.prefix}journal/{revision}")

    # Renaming ------------------------------------------------------------------------------------

    def remote_iri(self, iri: str) -> str:
        return self.graph_prefix + iri[len(GRAPH_NS) :] if iri.startswith(GRAPH_NS) else iri

    def local_iri(self, iri: str) -> str:
        if iri.startswith(self.graph_prefix):
            return GRAPH_NS + iri[len(self.graph_prefix) :]
        return iri

    def remote(self, term: Term) -> Term:
        if isinstance(term, NamedNode) and term.value.startswith(GRAPH_NS):
            return NamedNode(self.remote_iri(term.value))
        return term

    def local(self, term: Term) -> Term:
        if isinstance(term, NamedNode) and term.value.startswith(self.graph_prefix):
            return NamedNode(self.local_iri(term.value))
        return term

    def remote_graph(self, graph: NamedNode) -> NamedNode:
        return NamedNode(self.remote_iri(graph.value))

    def remote_quad(self, quad: Quad) -> Quad:
        graph = quad.graph_name
        return Quad(
            self.remote(quad.subject),  # type: ignore[arg-type]
            quad.predicate,
            self.remote(quad.object),
            self.remote(graph) if isinstance(graph, NamedNode) else graph,  # type: ignore[arg-type]
        )

    def rewrite_text(self, text: str) -> str:
        """``text`` (SPARQL or N-Triples) with Engram's graph IRIs renamed to this memory's."""
        return self._rewrite(text, self.remote_iri) if GRAPH_NS in text else text

    def restore_text(self, text: str) -> str:
        """The inverse of :meth:`rewrite_text`, for a server's N-Triples answer."""
        return self._rewrite(text, self.local_iri) if self.graph_prefix in text else text

    def restore_results_xml(self, data: bytes) -> bytes:
        """SPARQL XML results with this memory's graph IRIs renamed back to Engram's.

        In the XML format an IRI is exactly the text of a ``<uri>`` element, and a literal
        cannot hold an unescaped ``<``, so the replacement touches IRIs only.
        """
        old = b"<uri>" + self.graph_prefix.encode()
        return data.replace(old, b"<uri>" + GRAPH_NS.encode()) if old in data else data

    @staticmethod
    def _rewrite(text: str, rename: Callable[[str], str]) -> str:
        def one(match: re.Match[str]) -> str:
            iri = match.group(1)
            return match.group() if iri is None else f"<{rename(iri)}>"

        return _TOKENS.sub(one, text)
