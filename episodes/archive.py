"""An episode's recording moved to object storage when it ends, fetched back when it is read.

:class:`StreamArchive` joins the files (:mod:`episodes.streams.objects`) and the graph: after an
episode ends, its bag directory is uploaded write-once, and one transaction records each object
(``engram:streamObject`` on the episode and on its stream descriptors, with ``engram:byteSize``
and ``engram:sha256`` on the object); the local copy is then removed. Deleting an episode
deletes its objects.

Replay opens a stored recording in place (:meth:`StreamArchive.replayer`): ranged reads of the
MCAP file's summary, then of the chunks it replays (:mod:`episodes.streams.ranged`),
never the whole file first. The messages a replayer reads when it opens (the recording record,
providers and ticks, a few bytes in every chunk) are uploaded beside the MCAP file as a small
``<episode>.replay-messages`` object with the end of the MCAP file (its summary), read whole and
digest checked: opening then reads nothing of the recording itself. Export, and recordings
without a summary, call :meth:`StreamArchive.local`, which fetches the objects back (digest
checked) into the streams directory, the local cache. Fetched recordings are marked as such and
evicted least recently used first once they hold more than ``cache_bytes``; recordings made
here are never evicted.

If the upload fails the recording stays local (and the episode ended), so nothing recorded is
lost; :meth:`StreamArchive.archive` can be called again later.

>>> StreamArchive.__name__
'StreamArchive'
"""

import functools
import hashlib
import logging
import os
import shutil
from pathlib import Path

from pyoxigraph import Literal, NamedNode

from episodes.streams.bagwrite import mcap_file
from episodes.streams.errors import CorruptRecordingError, StreamError
from episodes.streams.mcapread import LIMIT_BYTES
from episodes.streams.objects import ObjectStore, StoredObject
from episodes.streams.ranged import SavedMessages, open_ranged, read_messages, write_messages
from episodes.streams.registry import bag_path
from episodes.streams.replay import Replayer
from episodes.streams.tick_writer import PROVIDERS_TOPIC, RECORDING_TOPIC, TICKS_TOPIC
from episodes.terms import episode_iri
from kg import Store
from ontologies.vocab import BYTE_SIZE, EPISODES, SHA256, STREAM_OBJECT

__all__ = ["StreamArchive"]

log = logging.getLogger(__name__)

FETCHED_MARK = ".engram-fetched"
"""A file in a bag directory fetched from storage (its modification time: the last use)."""
REPLAY_TOPICS = frozenset({RECORDING_TOPIC, PROVIDERS_TOPIC, TICKS_TOPIC})
"""What a replayer reads when it opens: saved beside a stored recording (see the module)."""
REPLAY_MESSAGES_SUFFIX = ".replay-messages"
CACHE_BYTES = 10 * 1024**3
"""Default bound of the fetched recordings kept in the local cache."""


class StreamArchive:
    """Episodes' recordings under ``streams_root`` (the local cache) and in ``objects``.

    ``cache_bytes`` bounds what fetched recordings may occupy there (see the module's summary);
    ``read_limit_bytes`` bounds each record and decompressed chunk a replayer reads
    (:mod:`episodes.streams.mcapread`).
    """

    def __init__(
        self,
        objects: ObjectStore,
        streams_root: Path,
        *,
        cache_bytes: int = CACHE_BYTES,
        read_limit_bytes: int = LIMIT_BYTES,
    ) -> None:
        if cache_bytes < 0:
            raise ValueError(f"cache_bytes: got {cache_bytes!r}, expected a size in bytes >= 0")
        self.objects = objects
        self.streams_root = streams_root
        self.cache_bytes = cache_bytes
        self.read_limit_bytes = read_limit_bytes

    def archive(self, store: Store, episode_id: str) -> list[StoredObject]:
        """Upload the ended episode's bag, record its objects, then drop the local copy.

        Returns the objects (none if the episode recorded nothing). Raises
        :class:`~episodes.streams.objects.ObjectStorageError` if the upload fails; the local
        recording is then kept.
        """
        bag = bag_path(self.streams_root, episode_id)
        if not bag.is_dir():
            return []
        _save_replay_messages(bag)
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

    def replayer(self, store: Store, episode_id: str) -> Replayer:
        """A replayer of the episode's recording: the local one if there is one, else the
        stored MCAP read by ranges (fetched whole only if it has no summary to read by).

        Raises :class:`~episodes.streams.objects.ObjectStorageError` if storage fails, and
        the replayer's errors for a missing or corrupt recording.
        """
        bag = bag_path(self.streams_root, episode_id)
        limit = self.read_limit_bytes
        if bag.is_dir():
            return Replayer(self.local(store, episode_id), limit_bytes=limit)
        stored = self.stored(store, episode_id)
        mcap = [s for s in stored if s.name.endswith(".mcap")]
        if len(mcap) == 1:
            read = functools.partial(self.objects.read_range, mcap[0].uri)
            try:
                saved = [s for s in stored if s.name.endswith(REPLAY_MESSAGES_SUFFIX)]
                found = self._saved_messages(saved[0]) if saved else None
                scan = open_ranged(
                    read,
                    mcap[0].size,
                    name=mcap[0].uri,
                    saved=found,
                    topics=REPLAY_TOPICS,
                    limit_bytes=limit,
                )
            except CorruptRecordingError as error:
                log.info("episode %s: fetching the whole recording: %s", episode_id, error)
            else:
                return Replayer(mcap[0].uri, scan=scan)
        return Replayer(self.local(store, episode_id), limit_bytes=limit)

    def _saved_messages(self, saved: StoredObject) -> SavedMessages:
        data = self.objects.read_range(saved.uri, 0, saved.size) if saved.size else b""
        if len(data) != saved.size or hashlib.sha256(data).hexdigest() != saved.sha256:
            raise CorruptRecordingError(f"{saved.uri} does not match its recorded sha256")
        return read_messages(data)

    def local(self, store: Store, episode_id: str) -> Path:
        """The episode's bag directory, fetched from storage first if it is not cached here."""
        bag = bag_path(self.streams_root, episode_id)
        mark = bag / FETCHED_MARK
        if bag.is_dir():
            if mark.exists():
                os.utime(mark)  # used now: evicted last
            return bag
        stored = self.stored(store, episode_id)
        if stored:
            try:
                self.objects.fetch_all(stored, bag)
                mark.touch()
            except OSError:
                if not bag.is_dir():  # not another reader's fetch that finished first
                    raise
            log.info("episode %s: recording fetched from storage", episode_id)
            self.evict(keep=bag)
        return bag

    def evict(self, *, keep: Path | None = None) -> list[Path]:
        """Remove fetched recordings, least recently used first, until they hold at most
        ``cache_bytes`` (``keep``, the one just fetched, stays). Returns those removed."""
        cached = []
        for mark in self.streams_root.glob(f"*/{FETCHED_MARK}"):
            try:
                used = mark.stat().st_mtime
                size = sum(f.stat().st_size for f in mark.parent.iterdir() if f.is_file())
            except OSError:
                continue  # removed meanwhile
            cached.append((used, size, mark.parent))
        total = sum(size for _, size, _ in cached)
        removed = []
        for _, size, bag in sorted(cached, key=lambda entry: entry[0]):
            if total <= self.cache_bytes:
                break
            if bag == keep:
                continue
            shutil.rmtree(bag, ignore_errors=True)
            total -= size
            removed.append(bag)
            log.info("evicted %s from the recordings cache (%d bytes)", bag.name, size)
        return removed

    def delete(self, objects: list[StoredObject]) -> None:
        """Delete the objects (read with :meth:`stored` before the episode's triples go)."""
        self.objects.delete(item.uri for item in objects)


def _save_replay_messages(bag: Path) -> None:
    """Save the replayer's opening messages beside a complete recording (best effort: without
    them a stored recording opens by reading a little of every chunk)."""
    mcap = mcap_file(bag)
    target = bag / f"{bag.name}{REPLAY_MESSAGES_SUFFIX}"
    if not mcap.is_file() or target.exists():
        return
    try:
        write_messages(mcap, REPLAY_TOPICS, target)
    except CorruptRecordingError:
        target.unlink(missing_ok=True)  # no summary (a crashed recording): read whole anyway
    except (OSError, StreamError) as error:
        target.unlink(missing_ok=True)
        log.warning("%s: replay messages not saved: %s", bag.name, error)
