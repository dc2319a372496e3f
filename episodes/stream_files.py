"""An episode memory's recordings: the open ones, their directories, their replayers.

One rosbag2 directory per episode under ``<data_dir>/streams`` (see
:class:`episodes.paths.DataPaths`), written while the episode runs by a recorder of the
process's :class:`episodes.streams.RecordingRegistry`, and read back by a
:class:`episodes.streams.Replayer`, from object storage by ranged reads once an ended episode's
recording has moved there (:class:`episodes.archive.StreamArchive`).

>>> import tempfile
>>> from kg import Store
>>> with tempfile.TemporaryDirectory() as tmp:
...     streams = StreamFiles(Store(), DataPaths(Path(tmp)), archive=None)
...     streams.path("e1").relative_to(tmp).as_posix()
'streams/e1'
"""

import shutil
from pathlib import Path

from episodes.archive import StreamArchive
from episodes.model import StreamDescriptor
from episodes.paths import DataPaths
from episodes.streamlink import descriptors_from_recording, descriptors_from_stats
from episodes.streams import RecordingRegistry, Replayer
from episodes.streams.mcapread import LIMIT_BYTES
from episodes.terms import check_id
from kg import Store

__all__ = ["StreamFiles"]


class StreamFiles:
    """The episodes' recordings of one memory.

    ``recordings`` is the process's registry of open recordings (one is made on first use when
    omitted); ``archive`` is where ended episodes' recordings go (object storage), if anywhere;
    ``read_limit_bytes`` bounds each record and decompressed chunk a replayer reads
    (:mod:`episodes.streams.mcapread`).
    """

    def __init__(
        self,
        store: Store,
        paths: DataPaths,
        archive: StreamArchive | None,
        *,
        recordings: RecordingRegistry | None = None,
        read_limit_bytes: int = LIMIT_BYTES,
    ) -> None:
        self.store = store
        self.paths = paths
        self.archive = archive
        self.read_limit_bytes = read_limit_bytes
        self._recordings = recordings

    @property
    def recordings(self) -> RecordingRegistry:
        """The registry of open recordings."""
        if self._recordings is None:
            self._recordings = RecordingRegistry()
        return self._recordings

    def path(self, episode_id: str) -> Path:
        """The rosbag2 directory of an episode's recording; raises
        :class:`~episodes.errors.EpisodeStateError` without a data directory."""
        return self.paths.streams(episode_id)

    def local(self, episode_id: str) -> Path:
        """The episode's recording as a directory to read: fetched from object storage if need
        be."""
        if self.archive is not None:
            return self.archive.local(self.store, check_id(episode_id, "episode"))
        return self.paths.streams(episode_id)

    def replayer(self, episode_id: str) -> Replayer:
        """A replayer of the episode's recording; one in object storage is read by ranges."""
        if self.archive is not None:
            return self.archive.replayer(self.store, check_id(episode_id, "episode"))
        return Replayer(self.path(episode_id), limit_bytes=self.read_limit_bytes)

    def open(self, episode_id: str) -> None:
        """Open a recording of the episode in its directory (see
        :meth:`episodes.streams.RecordingRegistry.open`)."""
        self.recordings.open(episode_id, self.path(episode_id))

    def abandon(self, episode_id: str) -> None:
        """Close the episode's recording and remove its directory (an episode that failed to
        begin)."""
        self.recordings.close(episode_id)
        shutil.rmtree(self.path(episode_id), ignore_errors=True)

    def stop(self, episode_id: str) -> None:
        """Close the episode's recording if one is open, without describing it."""
        if self._recordings is not None and episode_id in self._recordings:
            self._recordings.close(episode_id)

    def finish(self, episode_id: str) -> list[StreamDescriptor]:
        """Close the episode's recording if it is open and describe what its file holds (also
        a recording left by an earlier process); empty without stream files."""
        if self.paths.root is None and self._recordings is None:
            return []
        if episode_id in self.recordings:
            return descriptors_from_stats(
                self.recordings.close(episode_id), self.paths.dir("streams")
            )
        if self.paths.root is not None and self.path(episode_id).exists():
            replayer = Replayer(self.path(episode_id), limit_bytes=self.read_limit_bytes)
            return descriptors_from_recording(replayer, self.paths.dir("streams"))
        return []
