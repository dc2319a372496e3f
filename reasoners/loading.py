"""The scene memory's in-memory model: where it comes from, whether it is ready, what it mirrors.

A :class:`LoadedModel` reads the model from the index file beside the store when that file is
current, or rebuilds it from the store's triples (:mod:`reasoners.index_file`,
:func:`reasoners.persist.load_model`), optionally in a background thread; until it is ready, a
read of :attr:`LoadedModel.model` waits :data:`LOADING_WAIT_S` and then answers
:class:`~reasoners.errors.MemoryLoadingError`. It keeps the revision token of the store the
model mirrors, rebuilds the model when a write failed or another process changed the store, and
saves it to the index file. Its :attr:`~LoadedModel.lock` serialises every use of the model.

>>> from kg import Store
>>> loaded = LoadedModel(Store(), (1.0, 1.0, 1.0, 1.0))
>>> loaded.open()
>>> loaded.ready, loaded.source, len(loaded.model.graph.classes)
(True, 'store', 0)
"""

import logging
import threading
import time
from collections.abc import Callable

from kg.store import Store
from reasoners import index_file, persist
from reasoners.errors import MemoryLoadingError
from reasoners.model import MemoryModel

__all__ = ["LOADING_WAIT_S", "LoadedModel", "Weights"]

log = logging.getLogger(__name__)

Weights = tuple[float, float, float, float]
"""The policy's complexity, children, store and retrieve weights."""

LOADING_WAIT_S = 1.0
"""How long a call made while the memory opens in the background waits for it before answering
:class:`MemoryLoadingError`."""


class LoadedModel:
    """The model of the scene memory kept in ``store``, scored with ``weights``.

    Nothing is read until :meth:`open`.
    """

    def __init__(self, store: Store, weights: Weights) -> None:
        self.store = store
        self.weights = weights
        self.lock = threading.RLock()
        """Held by whoever reads or changes the model (re-entrant: an operation calls others)."""
        self.current: MemoryModel | None = None
        """The model, or None while it loads or after loading failed (:attr:`model` waits)."""
        self.revision: str | None = None
        """The store's revision token that the model mirrors."""
        self.saved_revision: str | None = None
        """The revision the index file holds (None: no file of this model's)."""
        self.rebuilding = False
        self.source = ""
        """Where the model came from: "index file", "store", or "" while it loads."""
        self._error: BaseException | None = None
        self._ready = threading.Event()

    def open(self, *, background: bool = False, then: Callable[[], None] = lambda: None) -> None:
        """Read the model from the index file, or rebuild it from the store, then run ``then``
        (still before the model counts as ready). In the ``background``, in a daemon thread
        that logs a failure; otherwise a failure is raised."""
        if background:
            threading.Thread(
                target=self._open,
                kwargs={"then": then, "background": True},
                name="engram-memory-open",
                daemon=True,
            ).start()
        else:
            self._open(then=then)

    def _open(self, *, then: Callable[[], None], background: bool = False) -> None:
        began = time.perf_counter()
        try:
            model, revision, source = index_file.open_model(
                self.store, self.weights, lambda: persist.load_model(self.store, self.weights)
            )
            # Not under the lock: a caller holding it may be waiting for this (see model).
            self.revision, self.source = revision, source
            self.saved_revision = revision if source == "index file" else None
            self.current = model
            then()
        except Exception as error:
            self.current, self._error = None, error
            self._ready.set()
            if not background:
                raise
            log.exception("scene memory could not be opened")
            return
        self._ready.set()
        log.info(
            "scene memory opened from the %s in %.2f s: %d classes, %d experienced scenes",
            source,
            time.perf_counter() - began,
            len(model.graph.classes),
            len(model.items.records),
        )

    @property
    def model(self) -> MemoryModel:
        """The in-memory model; :class:`MemoryLoadingError` while it is still being read."""
        model = self.current
        if model is None:
            self._ready.wait(LOADING_WAIT_S)  # a small memory is ready before the caller knows
            model = self.current
        if model is None:
            if self._error is not None:
                raise MemoryLoadingError(
                    f"scene memory unavailable: opening it failed: {self._error}"
                )
            raise MemoryLoadingError("scene memory unavailable: still loading, retry shortly")
        return model

    @property
    def ready(self) -> bool:
        """True once the model is loaded (False while loading or after a failed load)."""
        return self.current is not None

    def wait_ready(self, timeout_s: float | None = None) -> bool:
        """Wait until loading has finished (or failed); True if the memory is ready."""
        self._ready.wait(timeout_s)
        return self.ready

    def reload(self) -> None:
        """Rebuild the model from the store: after another Engram changed it (a follower of a
        shared memory) or a failed write left the model unsure (kg.remote)."""
        with self.lock:
            self.rebuild()

    def rebuild(self) -> None:
        """Read the model again from the store (the caller holds the lock). While it does,
        :attr:`rebuilding` is True: the score view of the model it replaces is not written."""
        self.rebuilding = True
        try:
            self.current = persist.load_model(self.store, self.weights)
            self.revision = index_file.stored_revision(self.store)
        finally:
            self.rebuilding = False

    def update(self, change: Callable[[MemoryModel], None]) -> None:
        """Run ``change`` on the model under the lock: a follower of a shared memory applying
        what the writer changed (reasoners.follow). If ``change`` raises, the model may be half
        changed: :meth:`reload` it."""
        with self.lock:
            change(self.model)

    def save_index(self) -> bool:
        """Save the model beside the store (see :mod:`reasoners.index_file`) if the store
        changed since the last save; True if a file was written. The store is flushed first,
        so that the file never names a revision the store could lose."""
        path = index_file.index_path(self.store)
        if path is None or not self.ready:
            return False
        with self.lock:
            revision = self.revision
            if revision is None or revision == self.saved_revision:
                return False
            self.store.flush()
            values = index_file.snapshot(self.model, revision, self.weights)
        index_file.write_snapshot(path, values)
        with self.lock:
            self.saved_revision = revision
        log.info("scene memory index saved at revision %s", revision)
        return True
