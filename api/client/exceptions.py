"""armor_py_api's exceptions, same names and messages, and one of Engram's for bad input.

ArmorPyException
├── ArmorServiceCallError       the server cannot be reached, or refused the request (HTTP 4xx/5xx)
└── ArmorServiceInternalError   the directive answered ``success=false`` (``exit_code`` kept)
    └── ArmorInputError (ValueError)  ... because of what was sent: the message says what
"""

__all__ = [
    "INPUT_EXIT_CODES",
    "ArmorInputError",
    "ArmorPyException",
    "ArmorServiceCallError",
    "ArmorServiceInternalError",
    "directive_error",
]

INPUT_EXIT_CODES = frozenset({101, 208, 210, 212})
"""The exit codes of a directive refused for its input: an unsupported type, bad arguments, bad
SPARQL, a bad primitive or a memory directive out of order (api/armor/errors.py)."""


class ArmorPyException(Exception):
    """Base of the client's exceptions."""

    def __init__(self, message: str) -> None:
        super().__init__(message)
        self.message = message


class ArmorServiceCallError(ArmorPyException):
    """The call itself failed: no server, a timeout, a refused token or a malformed request."""


class ArmorServiceInternalError(ArmorPyException):
    """The server ran the directive and answered ``success=false``.

    >>> str(ArmorServiceInternalError("busy", 102))
    'ARMOR internal error 102: busy'
    """

    def __init__(self, message: str, exit_code: int | str) -> None:
        self.exit_code = exit_code
        self.description = message
        super().__init__(f"ARMOR internal error {exit_code}: {message}")


class ArmorInputError(ArmorServiceInternalError, ValueError):
    """The directive was refused because of what was sent; the message says what was wrong.

    >>> str(ArmorInputError("args[1]: got 'Sphre', expected a primitive kind", 212))
    "args[1]: got 'Sphre', expected a primitive kind (ARMOR exit code 212)"
    """

    def __init__(self, message: str, exit_code: int | str) -> None:
        super().__init__(message, exit_code)
        self.message = f"{message} (ARMOR exit code {exit_code})"
        self.args = (self.message,)


def directive_error(description: str, exit_code: int | str) -> ArmorServiceInternalError:
    """The exception for a directive that answered ``success=false``: an
    :class:`ArmorInputError` when its exit code says the input was wrong."""
    code = int(exit_code) if str(exit_code).isdigit() else None
    kind = ArmorInputError if code in INPUT_EXIT_CODES else ArmorServiceInternalError
    return kind(description, exit_code)
