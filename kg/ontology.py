"""Load the Engram T-Box into the ``tbox`` graph, once per ontology version.

>>> from kg.store import Store
>>> store = Store()
>>> ensure_ontology(store).action
'loaded'
>>> ensure_ontology(store).action
'unchanged'
"""

import logging
from dataclasses import dataclass
from pathlib import Path
from typing import Literal

from pyoxigraph import NamedNode, RdfFormat, parse

from kg.store import Store
from ontologies import ENGRAM_TTL
from ontologies.vocab import OWL_ONTOLOGY, OWL_VERSION_IRI, RDF_TYPE, TBOX

__all__ = ["OntologyStatus", "ensure_ontology", "stored_version"]

log = logging.getLogger(__name__)


@dataclass(frozen=True)
class OntologyStatus:
    """What :func:`ensure_ontology` did, and the version now in the store."""

    action: Literal["loaded", "replaced", "unchanged"]
    version: NamedNode
    previous: NamedNode | None


def stored_version(store: Store, graph: NamedNode = TBOX) -> NamedNode | None:
    """The version IRI of the ontology held in ``graph``, or ``None`` if it holds none."""
    rows = store.select("tbox_version", graph=graph)
    version = rows[0]["version"] if rows else None
    return version if isinstance(version, NamedNode) else None


def ensure_ontology(
    store: Store, path: Path = ENGRAM_TTL, graph: NamedNode = TBOX
) -> OntologyStatus:
    """Make ``graph`` hold the ontology in ``path``, replacing an older version atomically.

    The version is the ontology's ``owl:versionIRI``; a file without one is refused with
    ``ValueError``, since it could never be told apart from the next edition.
    """
    version = file_version(path)
    previous = stored_version(store, graph)
    if previous == version:
        return OntologyStatus("unchanged", version, previous)
    with store.transaction() as tx:
        tx.clear_graph(graph)
        count = tx.load(path, format=RdfFormat.TURTLE, graph=graph)
    action: Literal["loaded", "replaced"] = "loaded" if previous is None else "replaced"
    log.info("ontology %s %s (%d triples)", version.value, action, count)
    return OntologyStatus(action, version, previous)


def file_version(path: Path) -> NamedNode:
    """The ``owl:versionIRI`` of the ontology described in the Turtle file ``path``."""
    quads = list(parse(path=path, format=RdfFormat.TURTLE))
    ontologies = {q.subject for q in quads if q.predicate == RDF_TYPE and q.object == OWL_ONTOLOGY}
    versions = [
        q.object for q in quads if q.subject in ontologies and q.predicate == OWL_VERSION_IRI
    ]
    if len(ontologies) != 1 or len(versions) != 1 or not isinstance(versions[0], NamedNode):
        raise ValueError(
            f"{path}: expected one owl:Ontology with one owl:versionIRI, "
            f"found {len(ontologies)} ontologies and {len(versions)} version IRIs"
        )
    return versions[0]
