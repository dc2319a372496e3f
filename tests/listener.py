"""A TCP server on loopback that records whether anything connected to it."""

import socket
import threading
from collections.abc import Iterator
from contextlib import contextmanager

__all__ = ["Listener", "listening"]


class Listener:
    """Accepts and closes connections on a loopback port until closed; ``contacted`` is set by
    the first one."""

    def __init__(self) -> None:
        self.socket = socket.create_server(("127.0.0.1", 0))
        self.socket.settimeout(0.1)
        self.port: int = self.socket.getsockname()[1]
        self.contacted = threading.Event()
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._accept, daemon=True)
        self._thread.start()

    def _accept(self) -> None:
        while not self._stop.is_set():
            try:
                connection, _ = self.socket.accept()
            except TimeoutError:
                continue
            self.contacted.set()
            connection.close()

    def close(self) -> None:
        self._stop.set()
        self._thread.join()
        self.socket.close()


@contextmanager
def listening() -> Iterator[Listener]:
    """A running :class:`Listener`, closed when the block ends."""
    listener = Listener()
    try:
        yield listener
    finally:
        listener.close()
