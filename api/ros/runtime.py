"""What ``engram ros`` serves: the memory opened through the composition root
(:func:`api.services.open_services`), as ``engram serve`` opens it, with its upkeep
(:meth:`~api.services.Services.upkeep`) in a thread while the node serves."""

import threading
from dataclasses import dataclass, field

from api.armor import ArmorEngine
from api.config import Settings
from api.services import Services, open_services
from reasoners.clock import SettableClock

__all__ = ["OpenedMemory", "open_memory"]


@dataclass
class OpenedMemory:
    """The opened memory and a thread that keeps it up until :meth:`close`."""

    services: Services
    period_s: float
    _stop: threading.Event = field(default_factory=threading.Event)
    _thread: threading.Thread | None = None

    @property
    def engine(self) -> ArmorEngine:
        return self.services.armor

    def start_upkeep(self) -> None:
        self._thread = threading.Thread(target=self._upkeep, name="memory-upkeep", daemon=True)
        self._thread.start()

    def _upkeep(self) -> None:
        while not self._stop.wait(self.period_s):
            self.services.upkeep()

    def close(self) -> None:
        """Stop the upkeep, then close the memory (index saved, store flushed and released)."""
        self._stop.set()
        if self._thread is not None:
            self._thread.join()
        self.services.close()


def open_memory(settings: Settings, *, create: bool = False) -> OpenedMemory:
    """Open the memory ``settings`` name (creating an empty one only with ``create``), with its
    SPARQL runner for QUERY SPARQL, and start its upkeep."""
    clock = SettableClock() if settings.clock_settable else None
    services = open_services(settings, create=create, clock=clock, background=True, serving=True)
    memory = OpenedMemory(services, settings.sleep_check_s)
    memory.start_upkeep()
    return memory
