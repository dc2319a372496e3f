"""An episode's recording moved to object storage when it ends, fetched back when it is read.

:class:`StreamArchive` joins the files (:mod:`episodes.streams.objects`) and the graph: after an
episode ends, its bag directory is uploaded write-once, and one transaction records each object
(``engram:streamObject`` on the episode and on its stream descriptors, with ``engram:byteSize``
and ``engram:sha256`` on the object); the local copy is then removed. Replay and export call
:meth:`StreamArchive.local` first, which fetches the objects back into the streams directory
(the local cache) when they are not there. Deleting an episode deletes its objects.

If the upload fails the recording stays local (and the episode ended), so nothing recorded is
lost; :meth:`StreamArchive.archive` can be called again later.

>>> StreamArchive.__name__
'StreamArchive'
"""

import logging
import shutil
from pathlib import Path

from pyoxigraph import Literal, NamedNode

from episodes.streams.objects import ObjectStore, StoredObject
from episodes.streams.registry import bag_path
from episodes.terms import episode_iri
from kg import Store
from ontologies.vocab import BYTE_SIZE, EPISODES, SHA256, STREAM_OBJECT

__all__ = ["StreamArchive"]

log = logging.getLogger(__name__)


class StreamArchive:
    """Episodes' recordings under ``streams_root`` (the local cache) and in ``objects``."""

    def __init__(self, objects: ObjectStore, streams_root: Path) -> None:
        self.objects = objects
        self.streams_root = streams_root

    def archive(self, store: Store, episode_id: str) -> list[StoredObject]:
        """Upload the ended episode's bag, record its objects, then drop the local copy.

        Returns the objects (none if the episode recorded nothing). Raises
        :class:`~episodes.streams.objects.ObjectStorageError` if the upload fails; the local
        recording is then kept.
        """
        bag = bag_path(self.streams_root, episode_id)
        if not bag.is_dir():
            return []
        stored = self.objects.upload_directory(bag, episode_id)
        episode = episode_iri(episode_id)
        rows = store.select("episodes_stream_descriptors", episode=episode)
        descriptors = [row["stream"] for row in rows]
        with store.transaction() as tx:
            for item in stored:
                obj = NamedNode(item.uri)
                tx.insert(episode, STREAM_OBJECT, obj, EPISODES)
                tx.insert(obj, BYTE_SIZE, Literal(item.size), EPISODES)
                tx.insert(obj, SHA256, Literal(item.sha256), EPISODES)
                if item.name.endswith(".mcap"):
                    for descriptor in descriptors:
                        tx.insert(descriptor, STREAM_OBJECT, obj, EPISODES)  # type: ignore[arg-type]
        shutil.rmtree(bag, ignore_errors=True)
        log.info("episode %s: recording moved to %d objects", episode_id, len(stored))
        return stored

    def stored(self, store: Store, episode_id: str) -> list[StoredObject]:
        """The objects the graph records for the episode."""
        rows = store.select("episodes_stream_objects", episode=episode_iri(episode_id))
        return [
            StoredObject(row["object"].value, int(row["size"].value), row["sha256"].value)
            for row in rows
        ]

    def local(self, store: Store, episode_id: str) -> Path:
        """The episode's bag directory, fetched from storage first if it is not cached here."""
        bag = bag_path(self.streams_root, episode_id)
        if bag.is_dir():
            return bag
        stored = self.stored(store, episode_id)
        if stored:
            try:
                self.objects.fetch_all(stored, bag)
            except OSError:
                if not bag.is_dir():  # not another reader's fetch that finished first
                    raise
            log.info("episode %s: recording fetched from storage", episode_id)
        return bag

    def delete(self, objects: list[StoredObject]) -> None:
        """Delete the objects (read with :meth:`stored` before the episode's triples go)."""
        self.objects.delete(item.uri for item in objects)
