"""The store, scene memory and directive engine that ``engram ros`` serves, built as
``engram serve`` builds them (api/main.py's lifespan), and their upkeep while serving.

:func:`open_memory` is the one place that builds them for the standalone node.
"""

import datetime as dt
import logging
import threading
from collections.abc import Callable
from dataclasses import dataclass, field

from api.armor import ArmorEngine
from api.armor.memory import sleep_if_due
from api.backend import OpenedStore, open_store
from api.config import Settings
from kg import ensure_ontology
from kg.sandbox import QueryRunner
from reasoners.clock import SettableClock
from reasoners.memory import SceneMemory

__all__ = ["OpenedMemory", "open_memory"]

log = logging.getLogger(__name__)


@dataclass
class OpenedMemory:
    """What the node answers with, and a thread that sleeps the memory when due and flushes
    the store (as the server's timer does) until :meth:`close`."""

    opened: OpenedStore
    runner: QueryRunner
    scene_memory: SceneMemory
    engine: ArmorEngine
    period_s: float
    _stop: threading.Event = field(default_factory=threading.Event)
    _thread: threading.Thread | None = None

    def start_upkeep(self) -> None:
        self._thread = threading.Thread(target=self._upkeep, name="memory-upkeep", daemon=True)
        self._thread.start()

    def _upkeep(self) -> None:
        store = self.opened.store
        flushed = store.generation
        while not self._stop.wait(self.period_s):
            if not self.scene_memory.ready:
                continue
            sleep_if_due(self.scene_memory)
            _logged(self.scene_memory.settle_view, "the score view could not be written")
            if store.generation != flushed:
                flushed = store.generation
                store.flush()

    def close(self) -> None:
        """Stop the upkeep, save the memory's index, flush and close the store."""
        self._stop.set()
        if self._thread is not None:
            self._thread.join()
        self.runner.close()
        if self.scene_memory.wait_ready(timeout_s=0):
            _logged(self.scene_memory.save_index, "the scene memory's index could not be saved")
        self.opened.store.flush()
        self.opened.close()


def _logged(action: Callable[[], object], failure: str) -> None:
    try:
        action()
    except Exception:
        log.exception(failure)


def _utc_now() -> dt.datetime:
    return dt.datetime.now(dt.UTC)


def open_memory(settings: Settings) -> OpenedMemory:
    """Open the store ``settings`` name and build the scene memory and engine on it."""
    opened = open_store(settings)
    status = ensure_ontology(opened.store)
    log.info("store %s: ontology %s %s", opened.where, status.version.value, status.action)
    runner = opened.runner(settings)
    clock = SettableClock() if settings.clock_settable else _utc_now
    scene_memory = SceneMemory(opened.store, clock=clock, background=True)
    opened.watch(scene_memory)
    engine = ArmorEngine(
        opened.store,
        scene_memory=scene_memory,
        sandbox=runner,
        max_list_length=settings.armor_max_list_length,
    )
    memory = OpenedMemory(opened, runner, scene_memory, engine, settings.sleep_check_s)
    memory.start_upkeep()
    return memory
