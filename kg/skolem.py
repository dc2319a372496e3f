"""Blank nodes in, skolem IRIs inside, blank nodes out.

SPARQL cannot name a blank node in ``DELETE DATA``, so a stored OWL class expression built from
blank nodes could only be deleted by pattern, which risks taking a neighbour's triples with it.
Inside the store every blank node is therefore an IRI under ``SKOLEM_PREFIX``; exports turn them
back into blank nodes.

>>> from pyoxigraph import BlankNode
>>> skolemiser = Skolemiser()
>>> node = BlankNode()
>>> skolemiser.term(node) == skolemiser.term(node)
True
>>> is_skolem(skolemiser.term(node))
True
"""

import uuid
from typing import Any

from pyoxigraph import BlankNode, NamedNode, Quad, Triple

from ontologies.vocab import SKOLEM_PREFIX

__all__ = ["Deskolemiser", "Skolemiser", "is_skolem"]


def is_skolem(term: object) -> bool:
    """True for an IRI that stands for a blank node."""
    return isinstance(term, NamedNode) and term.value.startswith(SKOLEM_PREFIX)


class Skolemiser:
    """Maps each distinct blank node to one fresh skolem IRI, for the lifetime of this object."""

    def __init__(self) -> None:
        self._iris: dict[BlankNode, NamedNode] = {}

    def term(self, term: Any) -> Any:
        """The skolem IRI standing for a blank node; any other term unchanged."""
        if isinstance(term, BlankNode):
            iri = self._iris.get(term)
            if iri is None:
                iri = self._iris[term] = NamedNode(SKOLEM_PREFIX + uuid.uuid4().hex)
            return iri
        return term

    def quad(self, quad: Quad) -> Quad:
        return Quad(
            self.term(quad.subject),
            quad.predicate,
            self.term(quad.object),
            self.term(quad.graph_name),
        )


class Deskolemiser:
    """Maps each skolem IRI back to one blank node, for the lifetime of this object."""

    def __init__(self) -> None:
        self._nodes: dict[str, BlankNode] = {}

    def term(self, term: Any) -> Any:
        """The blank node standing for a skolem IRI; any other term unchanged."""
        if isinstance(term, NamedNode) and term.value.startswith(SKOLEM_PREFIX):
            node = self._nodes.get(term.value)
            if node is None:
                node = self._nodes[term.value] = BlankNode()
            return node
        return term

    def triple(self, triple: Triple) -> Triple:
        return Triple(
            self.term(triple.subject),
            triple.predicate,
            self.term(triple.object),
        )
