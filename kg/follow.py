"""Following a memory another Engram writes: poll its revision, read what the journal names.

A follower opens a memory read-only (:class:`kg.remote.RemoteDataset` with ``read_only``) and
polls its revision. When the revision moves it reads the journal entries after the revision it
knew and tells the dataset's listeners which subjects changed, so an in-memory index reloads only
those; when an entry touched everything, or the entries it needs were trimmed from the journal,
it reports ``touched=None`` and the listeners rebuild everything.

>>> Follower.__name__
'Follower'
"""

import logging
import threading

from pyoxigraph import Literal, NamedNode

import sparql
from kg.errors import StoreError
from kg.remote import Change, RemoteDataset
from kg.sparql_text import bind_values
from ontologies.vocab import XSD_INTEGER

__all__ = ["Follower"]

log = logging.getLogger(__name__)


class Follower:
    """Keeps ``dataset`` up to date with the writer, polling every ``poll_s`` seconds."""

    def __init__(self, dataset: RemoteDataset, *, poll_s: float = 0.1) -> None:
        if not poll_s > 0:
            raise ValueError(f"poll_s: got {poll_s!r}, expected a positive number of seconds")
        self.dataset = dataset
        self.poll_s = poll_s
        self._stop = threading.Event()
        self._thread: threading.Thread | None = None

    def catch_up(self) -> Change | None:
        """Read the revision and the journal once; return the change reported, if any."""
        dataset = self.dataset
        known = dataset.revision
        latest = dataset.read_revision()
        if latest == known:
            return None
        ns = dataset.namespace
        text = bind_values(
            sparql.load("remote_journal"),
            {"control": ns.control, "since": _integer(known)},
        )
        rows = dataset.select_raw(
            text, default_graphs=[ns.control.value], named_graphs=[ns.control.value]
        )
        revisions = {int(row["revision"].value) for row in rows}
        # the writer started over, or the journal was trimmed: rebuild
        complete = latest > known and set(range(known + 1, latest + 1)) <= revisions
        subjects: set[NamedNode] = set()
        for row in rows:
            if int(row["revision"].value) > latest:
                continue
            if "everything" in row:
                complete = False
            if "touched" in row:
                subjects.add(NamedNode(ns.local_iri(row["touched"].value)))
        touched = frozenset(subjects) if complete else None
        change = Change(latest, touched)
        dataset.revision = latest
        dataset.forget_graphs()
        log.info(
            "memory %s: revision %d -> %d, %s",
            ns.name,
            known,
            latest,
            "rebuild" if touched is None else f"{len(touched)} subjects changed",
        )
        dataset.notify(change)
        return change

    def start(self) -> None:
        """Poll in a background thread until :meth:`stop`."""
        self._stop.clear()
        self._thread = threading.Thread(
            target=self._run, name=f"engram-follow-{self.dataset.namespace.name}", daemon=True
        )
        self._thread.start()

    def _run(self) -> None:
        while not self._stop.wait(self.poll_s):
            try:
                self.catch_up()
            except StoreError as error:
                log.warning("cannot follow memory %s yet: %s", self.dataset.namespace.name, error)
            except Exception:  # a listener's bug must not stop following
                log.exception("a listener failed while following %s", self.dataset.namespace.name)

    def stop(self) -> None:
        self._stop.set()
        if self._thread is not None:
            self._thread.join()


def _integer(value: int) -> Literal:
    return Literal(str(value), datatype=XSD_INTEGER)
