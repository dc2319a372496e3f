"""The root of Engram's exceptions, its four kinds, and the knowledge-graph layer's errors.

Every error Engram raises on purpose is an :class:`EngramError` of one of four kinds, which
decide its HTTP answer (``api/errors.py`` maps by kind, so a new error cannot become a 500)::

    EngramError
    ├── InvalidInputError (ValueError)     the request is malformed or out of range   4xx
    │   ├── InvalidValueError               one named field's value: field, value, expected 422
    │   ├── InvalidPrimitiveError           a primitive's field is missing or out of range 422
    │   ├── QuerySyntaxError (SyntaxError)  the SPARQL text does not parse            400
    │   ├── QueryTooDeepError               the text nests too deeply to be parsed     400
    │   ├── QueryTooLongError               the text is longer than the limit          413
    │   ├── UnsupportedQueryError           e.g. an unknown function                   400
    │   ├── QueryRefusedError               it would write or reach outside            403
    │   └── ResultTooLargeError             the result passed the size limit           400
    ├── NotFoundError (LookupError)        what was named does not exist              404
    ├── ConflictError                      it does not fit the current state          409
    └── UnavailableError                   the service cannot answer now              503
        ├── StoreError                      the store cannot be opened, read or written
        │   ├── StoreLockedError            the directory is held by another process
        │   ├── TransactionError            a transaction was not applied; nothing written
        │   ├── StoreUnavailableError       the SPARQL server holding the memory is away
        │   ├── LeaseHeldError              another Engram writes this memory on the server
        │   └── ReadOnlyStoreError          this Engram follows the memory (answered 409)
        ├── QueryTimeoutError (TimeoutError) the query ran past its time limit
        └── QueryWorkerCrashedError          the query's worker died; it was replaced

``QueryError`` is a second base of every query error, for callers that catch them together.
"""

__all__ = [
    "ConflictError",
    "EngramError",
    "InvalidInputError",
    "InvalidPrimitiveError",
    "InvalidValueError",
    "LeaseHeldError",
    "NotFoundError",
    "QueryError",
    "QueryRefusedError",
    "QuerySyntaxError",
    "QueryTimeoutError",
    "QueryTooDeepError",
    "QueryTooLongError",
    "QueryWorkerCrashedError",
    "ReadOnlyStoreError",
    "ResultTooLargeError",
    "StoreError",
    "StoreLockedError",
    "StoreUnavailableError",
    "TransactionError",
    "UnavailableError",
    "UnsupportedQueryError",
]


class EngramError(Exception):
    """Base of every error Engram raises on purpose."""


class InvalidInputError(EngramError, ValueError):
    """The request is malformed or out of range; nothing was changed."""


class InvalidValueError(InvalidInputError):
    """One named field has a value that is not what was expected.

    >>> str(InvalidValueError("n", 0, "a whole number from 1"))
    'n: got 0, expected a whole number from 1'
    """

    def __init__(self, field: str, value: object, expected: str) -> None:
        self.field, self.value, self.expected = field, value, expected
        super().__init__(f"{field}: got {value!r}, expected {expected}")


class InvalidPrimitiveError(InvalidInputError):
    """A primitive's field is missing, malformed or out of range (:mod:`kg.primitive`)."""


class NotFoundError(EngramError, LookupError):
    """What the request names does not exist."""

    def __str__(self) -> str:  # a KeyError subclass would quote the message
        return str(self.args[0]) if self.args else ""


class ConflictError(EngramError):
    """The request does not fit the current state (ended twice, already open, ...)."""


class UnavailableError(EngramError):
    """The service cannot answer now; the same request may succeed later."""


class StoreError(UnavailableError):
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


class QuerySyntaxError(QueryError, InvalidInputError, SyntaxError):
    """The SPARQL text does not parse; the message holds the parser's line and column."""

    def __init__(self, message: str) -> None:
        SyntaxError.__init__(self, message)  # ValueError's __init__ comes first and sets no msg


class QueryTooDeepError(QueryError, InvalidInputError):
    """The SPARQL text nests more levels than the configured limit."""


class QueryTooLongError(QueryError, InvalidInputError):
    """The SPARQL text is longer than the configured limit."""


class UnsupportedQueryError(QueryError, InvalidInputError):
    """The query parses but cannot be evaluated here, e.g. it calls an unknown function."""


class QueryRefusedError(QueryError, InvalidInputError):
    """The query is not allowed here: it would modify the store or call another service."""


class ResultTooLargeError(QueryError, InvalidInputError):
    """The serialised result grew past the configured size limit."""


class QueryTimeoutError(QueryError, UnavailableError, TimeoutError):
    """The query ran longer than its time limit and was stopped."""


class QueryWorkerCrashedError(QueryError, UnavailableError):
    """The worker process running the query died; a new one has taken its place."""
