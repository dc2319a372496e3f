"""How routes read the name of a learned class or experienced scene from a request."""

from pyoxigraph import NamedNode

from kg.errors import InvalidValueError
from ontologies.vocab import ENGRAM_NS

__all__ = ["memory_iri"]


def memory_iri(text: str, field: str) -> NamedNode:
    """A short name in Engram's namespace (``Scene-4``) or a full IRI, angle brackets allowed.

    Raises :class:`~kg.errors.InvalidValueError` naming ``field`` for text that is not an IRI.

    >>> memory_iri("Scene-4", "class").value
    'https://w3id.org/engram/ontology#Scene-4'
    """
    value = text.strip().strip("<>")
    if ":" not in value:
        value = ENGRAM_NS + value
    try:
        return NamedNode(value)
    except ValueError:
        raise InvalidValueError(field, text, "a class or scene name, or an IRI") from None
