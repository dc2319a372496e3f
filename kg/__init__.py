"""The knowledge-graph store: the only package that touches ``pyoxigraph.Store``.

The names below are loaded on first use (PEP 562), so that importing a leaf module of the
package (:mod:`kg.errors`, :mod:`kg.primitive`, which the Python client needs) does not load
the store, pyoxigraph or rdflib. The exporter is :func:`kg.export.export` (``kg.export`` is
its module, whichever is imported first).
"""

import importlib
from typing import TYPE_CHECKING

from kg.errors import (
    EngramError,
    QueryError,
    QueryRefusedError,
    QuerySyntaxError,
    QueryTimeoutError,
    ResultTooLargeError,
    StoreError,
    StoreLockedError,
    TransactionError,
)

if TYPE_CHECKING:
    from kg.export import DEFAULT_GRAPHS, export_triples
    from kg.ontology import OntologyStatus, ensure_ontology, stored_version
    from kg.store import Store, Tracer
    from kg.transaction import Transaction

__all__ = [
    "DEFAULT_GRAPHS",
    "EngramError",
    "OntologyStatus",
    "QueryError",
    "QueryRefusedError",
    "QuerySyntaxError",
    "QueryTimeoutError",
    "ResultTooLargeError",
    "Store",
    "StoreError",
    "StoreLockedError",
    "Tracer",
    "Transaction",
    "TransactionError",
    "ensure_ontology",
    "export_triples",
    "stored_version",
]

_LAZY = {
    "DEFAULT_GRAPHS": "kg.export",
    "export_triples": "kg.export",
    "OntologyStatus": "kg.ontology",
    "ensure_ontology": "kg.ontology",
    "stored_version": "kg.ontology",
    "Store": "kg.store",
    "Tracer": "kg.store",
    "Transaction": "kg.transaction",
}


def __getattr__(name: str) -> object:
    """Load ``name`` from its module on first use; AttributeError for any other name."""
    if name not in _LAZY:
        raise AttributeError(f"module 'kg' has no attribute {name!r}")
    value = getattr(importlib.import_module(_LAZY[name]), name)
    globals()[name] = value
    return value
