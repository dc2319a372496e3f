"""Exit codes and the exceptions a directive raises to answer with one.

ARMOR's codes (``armor-protocol.md`` §7) and Engram's extensions, all answered with HTTP 200 and
``success=false`` unless noted::

    DirectiveError(exit_code, description)    base: becomes the directive's response
    ├── UnknownReferenceError   207  the reference was never loaded (ARMOR: a null-pointer 205)
    ├── InvalidArgumentsError   208  too few args, a bad number, flag, reasoner or name
    ├── ResourceError           209  a file or URL cannot be read, parsed or written
    ├── SparqlError             210  SPARQL that does not parse, is not a SELECT, or timed out
    ├── MemoryDirectiveError    212  a memory directive out of order or with a bad primitive
    └── ReasonerFailure         214  REASON cannot run: no reasoner, or a rule it cannot use
"""

from kg.errors import EngramError, InvalidInputError

__all__ = [
    "ABORTED",
    "BUSY",
    "CANNOT_MOUNT",
    "INTERNAL_ERROR",
    "INVALID_ARGUMENTS",
    "MEMORY_ERROR",
    "NO_COMMAND",
    "NO_REFERENCE",
    "OK",
    "REASONER_ERROR",
    "RESOURCE_ERROR",
    "SPARQL_ERROR",
    "UNKNOWN_COMMAND",
    "UNKNOWN_REFERENCE",
    "UNSUPPORTED_TYPE",
    "DirectiveError",
    "DirectiveListTooLongError",
    "InvalidArgumentsError",
    "MemoryDirectiveError",
    "ReasonerFailure",
    "ResourceError",
    "SparqlError",
    "UnknownReferenceError",
]

OK = 0
UNSUPPORTED_TYPE = 101
BUSY = 102
NO_REFERENCE = 201
NO_COMMAND = 202
CANNOT_MOUNT = 203
UNKNOWN_COMMAND = 205
# Engram's extensions: what ARMOR let crash the ROS call or reported as a null-pointer 205.
UNKNOWN_REFERENCE = 207
INVALID_ARGUMENTS = 208
RESOURCE_ERROR = 209
SPARQL_ERROR = 210
ABORTED = 211
"""Not used in responses today; reserved for directives skipped after a failure."""
MEMORY_ERROR = 212
INTERNAL_ERROR = 213
"""A bug or a store failure; the directive (and its list) changed nothing."""
REASONER_ERROR = 214


class DirectiveError(EngramError):
    """A directive that cannot be carried out; the message becomes ``error_description``.
    The engine answers it with its ARMOR exit code; it never reaches the HTTP layer."""

    exit_code = 205
    success = False
    timeout = False

    def __init__(self, description: str, exit_code: int | None = None) -> None:
        super().__init__(description)
        self.description = description
        if exit_code is not None:
            self.exit_code = exit_code


class UnknownReferenceError(DirectiveError):
    """The directive names a reference that was never loaded (or was dropped)."""

    exit_code = UNKNOWN_REFERENCE


class InvalidArgumentsError(DirectiveError):
    """The directive's arguments are missing or malformed."""

    exit_code = INVALID_ARGUMENTS


class ResourceError(DirectiveError):
    """A file or URL could not be read, parsed or written."""

    exit_code = RESOURCE_ERROR


class SparqlError(DirectiveError):
    """A QUERY SPARQL text was refused, did not parse, or ran out of time."""

    exit_code = SPARQL_ERROR

    def __init__(self, description: str, *, timeout: bool = False) -> None:
        super().__init__(description)
        self.timeout = timeout


class MemoryDirectiveError(DirectiveError):
    """A memory directive out of order (no open scene, …) or with an unusable primitive."""

    exit_code = MEMORY_ERROR


class ReasonerFailure(DirectiveError):
    """REASON cannot run: no reasoner installed, or the ontology holds a rule it cannot use."""

    exit_code = REASONER_ERROR


class DirectiveListTooLongError(InvalidInputError):
    """A directive list holds more directives than the configured maximum (HTTP 422)."""

    def __init__(self, length: int, maximum: int) -> None:
        self.field, self.value = "armor_requests", length
        self.expected = f"at most {maximum} directives (ENGRAM_ARMOR_MAX_LIST_LENGTH)"
        super().__init__(
            f"armor_requests: got a list of {length} directives, expected {self.expected}; "
            "split it into several lists"
        )
