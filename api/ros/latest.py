"""A one-slot mailbox: a consumer slower than its producer gets the newest item, never a queue."""

import threading
from typing import Generic, TypeVar

__all__ = ["Latest"]

T = TypeVar("T")


class Latest(Generic[T]):
    """Holds at most one item: :meth:`put` replaces one not yet taken (counted in
    ``replaced``); :meth:`take` waits for an item, or returns None once :meth:`close` d.

    >>> box: Latest[int] = Latest()
    >>> box.put(1), box.put(2), box.take(), box.replaced
    (False, True, 2, 1)
    >>> box.close(); box.take() is None
    True
    """

    def __init__(self) -> None:
        self.replaced = 0
        self._item: T | None = None
        self._closed = False
        self._ready = threading.Condition()

    def put(self, item: T) -> bool:
        """Offer ``item``; True if it replaced one that was waiting."""
        with self._ready:
            replacing = self._item is not None
            self.replaced += replacing
            self._item = item
            self._ready.notify()
            return replacing

    def take(self) -> T | None:
        """The item, once there is one (then the box is empty); None once closed."""
        with self._ready:
            while self._item is None and not self._closed:
                self._ready.wait()
            if self._closed:
                return None
            item, self._item = self._item, None
            return item

    def close(self) -> None:
        """Wake the consumer for good: :meth:`take` returns None from now on."""
        with self._ready:
            self._closed = True
            self._ready.notify_all()
