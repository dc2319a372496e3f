"""The latest stored scene for the live views, read by one producer per server.

Every open live view wants the scene stored last, each time a write stores a newer one. Read
per stream, 50 open views cost 50 queries per write and 250 looks at the store a second; read
here, a write costs one query whatever the number of views. :class:`LatestScene` watches the
store's write counter (an integer read, every ``check_s``) while at least one view is open,
reads the latest scene once per change, and wakes the views waiting for a newer one. With no
view open it does nothing.
"""

import asyncio
import logging
from collections.abc import AsyncIterator
from contextlib import asynccontextmanager, suppress

from starlette.concurrency import run_in_threadpool

from api.views import scenes
from api.views.models import SceneDetail
from kg import Store

__all__ = ["LatestScene"]

log = logging.getLogger(__name__)


class LatestScene:
    """The store's latest scene, kept current while someone watches (see the module)."""

    def __init__(self, store: Store, *, check_s: float) -> None:
        self.store = store
        self.check_s = check_s
        self.scene: SceneDetail | None = None
        """The latest scene as last read (None before the first read or while none is stored)."""
        self.version = 0
        """Grows by one each time :attr:`scene` changes, and at the first read."""
        self._changed = asyncio.Condition()
        self._watchers = 0
        self._task: asyncio.Task[None] | None = None

    @asynccontextmanager
    async def watching(self) -> AsyncIterator["LatestScene"]:
        """Keep the scene current while the context lasts (the producer runs while any
        context is open)."""
        self._watchers += 1
        if self._task is None or self._task.done():
            self.scene = None  # read while nobody watched: maybe no longer the latest
            self._task = asyncio.create_task(self._produce())
        try:
            yield self
        finally:
            self._watchers -= 1
            if self._watchers == 0 and self._task is not None:
                self._task.cancel()
                self._task = None

    async def newer(self, seen: int, *, timeout_s: float) -> int:
        """Wait until :attr:`version` differs from ``seen`` or ``timeout_s`` has passed; the
        version then."""
        async with self._changed:
            with suppress(TimeoutError):
                await asyncio.wait_for(
                    self._changed.wait_for(lambda: self.version != seen), timeout_s
                )
            return self.version

    async def _produce(self) -> None:
        generation = -1
        shown: str | None = None
        while True:
            if self.store.generation != generation:
                generation = self.store.generation
                try:
                    found = await run_in_threadpool(scenes.latest_scene, self.store)
                except Exception:  # the store closing under it, say: the next look retries
                    log.warning("the latest scene could not be read", exc_info=True)
                    generation = -1
                    found = self.scene
                iri = None if found is None else found.scene.iri
                if iri != shown or self.version == 0:
                    shown = iri
                    async with self._changed:
                        self.scene = found
                        self.version += 1
                        self._changed.notify_all()
            await asyncio.sleep(self.check_s)
