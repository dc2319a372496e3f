"""How the scene memory's writes reach the store: a transaction per operation, or one batch.

:meth:`Transactions.write` gives an operation one transaction (:meth:`kg.store.Store.transaction`)
whose writes compose in order (:class:`reasoners.batch.PendingWrites`); if anything fails, the
model is rebuilt from the store, which the failed transaction left as it was. Inside
:meth:`Transactions.batch`, the operations write into one set of pending writes that the caller
commits with its own. Each transaction records the store revision the model now mirrors
(:mod:`reasoners.index_file`).

An update leaves the score view (:mod:`reasoners.score_view`) to the next read: the store calls
:meth:`Transactions.settle_view` before every read, which writes the view once for all the
updates since the last one (on a shared server, which other robots read directly, each update
writes it in its own transaction instead).
"""

import datetime as dt
import logging
import threading
from collections.abc import Callable, Iterator
from contextlib import contextmanager

from kg.transaction import QuadReader
from reasoners import history, index_file
from reasoners.batch import PendingWrites
from reasoners.clock import SettableClock
from reasoners.loading import LoadedModel
from reasoners.score_view import ScoreView

__all__ = ["Transactions"]

log = logging.getLogger(__name__)


class Transactions:
    """The transactions of the memory whose model is ``loaded`` and whose view is ``view``;
    ``clock`` is the memory's (a settable one is put back when a batch fails)."""

    def __init__(
        self, loaded: LoadedModel, view: ScoreView, clock: Callable[[], dt.datetime]
    ) -> None:
        self.loaded = loaded
        self.view = view
        self.clock = clock
        self.store = loaded.store
        self.view_in_each_update = self.store.remote is not None
        """Write the score view in every update's transaction instead of before the next read:
        the default on a shared server, which other robots read directly, past this process's
        read barrier (set before the first update)."""
        self.reader: QuadReader = self.store
        """The store as the running operation sees it (its own pending writes included)."""
        self._batch: PendingWrites | None = None
        self._flush_after_batch = False
        """A large transaction wrote into the open batch (see :meth:`write`)."""
        self._counters = threading.Lock()
        self.begun = 0
        """Updates that left the view to be written, counted just before they commit."""
        self.viewed = 0
        """How many of those the written view includes."""
        self._wanted = 0
        """The most a reader is waiting for: a writer writes the view before it lets go."""
        self._later: list[Callable[[], object]] | None = None
        """The work :meth:`alongside` left for the running transaction's write."""

    @contextmanager
    def write(
        self, *, refresh_alongside: bool = False, view: bool = False, large: bool = False
    ) -> Iterator[PendingWrites]:
        """One transaction; if anything fails, the model is rebuilt from the store.

        A ``large`` transaction (a sleep pass) is followed by a flush in the background
        (:meth:`kg.store.Store.flush_in_background`), once the batch commits inside a
        :meth:`batch`: the updates after it then cost what they cost in a settled store.

        With ``refresh_alongside``, the model's pending re-scoring (the ancestors of what the
        transaction touched) runs while the store applies the write, instead of before it, and
        so does the work given to :meth:`alongside` inside the block.
        The transaction writes the score view with ``view`` or on a shared server; otherwise
        the view is marked stale for :meth:`settle_view`. Inside a :meth:`batch`, the writes go
        to the batch instead, which its owner commits or rolls back.
        """
        view = view or self.view_in_each_update
        loaded = self.loaded
        with loaded.lock:
            if self._batch is not None:  # the batch's owner commits, or rolls back
                if not view:
                    self.begun += 1  # its commit is the owner's: a reader arriving waits
                self._read_history_epoch()
                yield self._batch
                if view:
                    self.view.write(self._batch)
                self._flush_after_batch = self._flush_after_batch or large
                return
            alongside: Callable[[], None] | None = None
            later: list[Callable[[], object]] = []
            if refresh_alongside:

                def alongside() -> None:
                    loaded.model.scores.refresh()
                    for work in later:
                        work()

            revision = index_file.new_revision()
            outer, self._later = self._later, later if refresh_alongside else None
            try:
                with self.store.transaction(alongside=alongside) as tx:
                    writes = PendingWrites()
                    self.reader = writes.view(self.store)
                    self._read_history_epoch()
                    yield writes
                    if view:
                        self.view.write(writes)
                    if not writes.is_empty:  # the index file names the revision it mirrors
                        index_file.record_revision(writes, loaded.revision, revision)
                        if not view:
                            self.begun += 1  # before the commit: no reader may miss it
                    writes.copy_into(tx)
                if not writes.is_empty:
                    loaded.revision = revision
                    if large:
                        self.store.flush_in_background()
            except BaseException:
                if loaded.current is not None:  # not while it loads: the loader will set it
                    loaded.rebuild()
                raise
            finally:
                self.reader, self._later = self.store, outer
            if not view:
                self._let_go()

    def alongside(self, work: Callable[[], object]) -> None:
        """Run ``work`` while the store applies the running transaction's write (a
        :meth:`write` with ``refresh_alongside``), after the model's re-scoring; at once
        anywhere else (inside a batch, whose owner commits later, or another transaction).
        ``work`` must not feed the write: what it changes is not written. Its exceptions
        propagate once the write has finished, which they do not undo."""
        if self._later is None:
            work()
        else:
            self._later.append(work)

    def _read_history_epoch(self) -> None:
        model = self.loaded.model
        if model.state.history_epoch is None:  # a model just loaded or rebuilt
            model.state.history_epoch = history.current_epoch(self.reader)

    @contextmanager
    def batch(self) -> Iterator[PendingWrites]:
        """Run several operations into one set of writes that the caller commits.

        Inside the ``with`` block, every operation of the memory writes into the yielded
        :class:`~reasoners.batch.PendingWrites` instead of committing, each seeing the ones
        before it. The caller adds those writes to its own transaction and commits it inside the
        block. The model's lock is held for the whole block, so no other thread sees the model
        between the operations and the commit; if the block raises (an operation failed, or the
        commit did), the model is rebuilt from the store, which the failed commit left as it
        was, and a settable clock is put back.
        """
        # a shared store catches up after a failed write now, not at this batch's commit
        self.store.settle()
        loaded = self.loaded
        with loaded.lock:
            if self._batch is not None:
                raise RuntimeError("batch: a batch is already open on this memory")
            writes = PendingWrites()
            # the index file names the revision it mirrors: the batch's commit makes a new one
            revision = index_file.new_revision()
            index_file.record_revision(writes, loaded.revision, revision)
            self._batch, self.reader = writes, writes.view(self.store)
            clock = self.clock
            saved = clock.snapshot() if isinstance(clock, SettableClock) else None
            try:
                yield writes
                loaded.revision = revision
            except BaseException:
                loaded.rebuild()
                if isinstance(clock, SettableClock):
                    clock.restore(saved)
                raise
            finally:
                self._batch, self.reader = None, self.store
                large, self._flush_after_batch = self._flush_after_batch, False
            if large:
                self.store.flush_in_background()
            self._let_go()

    def settle_view(self) -> None:
        """Write the score view's pending changes in one transaction, if an update committed
        before this call left any; the store calls it before every read
        (:meth:`kg.store.Store.settle_reads`), so a reader never sees a stale view.

        An update writes the class it touched, its edges and its experienced scene; the score
        terms of its ancestors (a class's score depends on its children's) wait for the next
        read, so that the updates between two reads rewrite each changed class once. While
        another thread holds the memory (an update in progress), the caller waits for that
        thread to write the view as it lets go. Nothing is written while a batch of this thread
        is open (it has not committed yet) or while the model loads."""
        target = self.begun
        lock, loaded = self.loaded.lock, self.loaded
        while self.viewed < target:
            if lock.acquire(blocking=False):  # free, or this thread's own
                try:
                    if self._batch is None and loaded.current is not None and not loaded.rebuilding:
                        self._want(target)
                        self._write_view_if_wanted()
                finally:
                    lock.release()
                return
            self._want(target)  # the holder writes it as it lets go, or this thread does
            if lock.acquire(timeout=0.01):
                lock.release()

    def _want(self, target: int) -> None:
        with self._counters:
            self._wanted = max(self._wanted, target)

    def _write_view_if_wanted(self) -> None:
        """Under the lock: write the view of every update begun so far if a reader waits for
        it."""
        if self._wanted <= self.viewed:
            return
        upto = self.begun
        with self.write(view=True):
            pass
        with self._counters:
            self.viewed = max(self.viewed, upto)

    def _let_go(self) -> None:
        """After a committed update, still under the lock: write the view if a reader waits
        (a failure is left to the reader, which tries again and reports it)."""
        try:
            self._write_view_if_wanted()
        except Exception:
            log.exception("scene memory: the score view could not be written after an update")
