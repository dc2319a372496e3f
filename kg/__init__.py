"""The knowledge-graph store: the only package that touches ``pyoxigraph.Store``."""

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
from kg.export import DEFAULT_GRAPHS, export, export_triples
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
    "export",
    "export_triples",
    "stored_version",
]
