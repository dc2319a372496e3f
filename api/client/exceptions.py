"""armor_py_api's exceptions, same names and messages.

ArmorPyException
├── ArmorServiceCallError       the server cannot be reached, or refused the request (HTTP 4xx/5xx)
└── ArmorServiceInternalError   the directive answered ``success=false`` (``exit_code`` kept)
"""

__all__ = ["ArmorPyException", "ArmorServiceCallError", "ArmorServiceInternalError"]


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
