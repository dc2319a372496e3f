"""The exceptions of the knowledge-graph layer.

EngramError
├── StoreError
│   ├── StoreLockedError        the store directory is held by another process
│   ├── TransactionError        a transaction could not be applied; nothing was written
│   ├── StoreUnavailableError   the SPARQL server holding the memory cannot be reached
│   ├── LeaseHeldError          another Engram writes this memory on the shared server
│   └── ReadOnlyStoreError      this Engram follows a memory and may not write it
└── QueryError
    ├── QuerySyntaxError        the SPARQL text does not parse (also a SyntaxError)
    ├── QueryRefusedError       the query would write, or reach outside the store
    ├── QueryTimeoutError       the query ran past its time limit and was stopped
    └── ResultTooLargeError     the serialised result passed the size limit
"""

__all__ = [
    "EngramError",
    "LeaseHeldError",
    "QueryError",
    "QueryRefusedError",
    "QuerySyntaxError",
    "QueryTimeoutError",
    "ReadOnlyStoreError",
    "ResultTooLargeError",
    "StoreError",
    "StoreLockedError",
    "StoreUnavailableError",
    "TransactionError",
]


class EngramError(Exception):
    """Base of every error Engram raises on purpose."""


class StoreError(EngramError):
    """The store could not be opened, read or written."""


class StoreLockedError(StoreError):
    """The store directory is already opened for writing by another process."""


class TransactionError(StoreError):
    """A transaction could not be applied; the store is unchanged."""


class StoreUnavailableError(StoreError):
    """The SPARQL server holding the memory did not answer; retry when it is back."""


class LeaseHeldError(StoreError):
    """Another Engram holds the writer's lease of this memory on the shared server."""


class ReadOnlyStoreError(StoreError):
    """This Engram follows a memory on a shared server read-only and may not write it."""


class QueryError(EngramError):
    """A SPARQL query could not be answered."""


class QuerySyntaxError(QueryError, SyntaxError):
    """The SPARQL text does not parse; the message holds the parser's line and column."""


class QueryRefusedError(QueryError):
    """The query is not allowed here: it would modify the store or call another service."""


class QueryTimeoutError(QueryError, TimeoutError):
    """The query ran longer than its time limit and was stopped."""


class ResultTooLargeError(QueryError):
    """The serialised result grew past the configured size limit."""
