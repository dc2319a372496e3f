"""An episode memory's bag imports: a ROS 1 bag file or a ROS 2 bag directory becomes a finished
episode with the bag's samples as its recording (see :mod:`episodes.bag_import`, which does the
work, and its limits in :mod:`episodes.bag_limits`).
"""

from collections.abc import Sequence
from pathlib import Path

from episodes import bag_import
from episodes.bag_import import BagEpisode
from episodes.bag_limits import DEFAULT_LIMIT_BYTES
from episodes.lifecycle import ArgumentSpec
from episodes.model import Episode, ImportReport
from episodes.paths import DataPaths
from episodes.times import now
from kg import Store
from kg.clock import Clock

__all__ = ["BagImports"]


class BagImports:
    """The bag imports of one memory, whose stream files are laid out by ``paths``; ``clock``
    gives "now" (a bag's times are its own)."""

    def __init__(self, store: Store, paths: DataPaths, *, clock: Clock) -> None:
        self.store = store
        self.paths = paths
        self.clock = clock

    def bag(
        self,
        path: Path | str,
        activity: str,
        *,
        activity_type: str | None = None,
        arguments: Sequence[ArgumentSpec] = (),
        episode_id: str | None = None,
    ) -> Episode:
        """Import a ROS 1 bag file or ROS 2 bag directory as a finished episode.

        The samples become the episode's recording (channels mapped, times kept, see
        ``episodes.streams.import_bag``); the episode begins and ends with the bag's first and
        last message and carries an ``imported_from`` annotation (and one ``skipped_topic``
        annotation per topic of a type that cannot be imported). The scene memory's state at
        the time is unknown, so no snapshots are recorded. Nothing stays behind on failure.
        :meth:`bag_report` also returns what was skipped.
        """
        return self.bag_report(
            path, activity, activity_type=activity_type, arguments=arguments, episode_id=episode_id
        ).episode

    def bag_report(
        self,
        path: Path | str,
        activity: str,
        *,
        activity_type: str | None = None,
        arguments: Sequence[ArgumentSpec] = (),
        episode_id: str | None = None,
        name: str | None = None,
        max_decompressed_bytes: int = DEFAULT_LIMIT_BYTES,
    ) -> ImportReport:
        """:meth:`bag`, answering the episode and the topics skipped (type and count).
        ``name`` is how messages and the ``imported_from`` annotation call the bag (default:
        ``path``); a compressed piece of the bag may expand to ``max_decompressed_bytes``.
        Raises :class:`~episodes.bag_limits.DamagedBagError` if the bag cannot be read."""
        what = BagEpisode(activity, activity_type, arguments, episode_id)
        return bag_import.import_report(
            self.store,
            self.paths,
            path,
            what,
            now=now(self.clock),
            name=name,
            max_decompressed_bytes=max_decompressed_bytes,
        )

    def source(self, path: str) -> Path:
        """The bag at ``path`` inside the data directory, for an HTTP client (see
        :func:`episodes.bag_import.import_source`)."""
        return bag_import.import_source(self.paths, path)

    @property
    def uploads_dir(self) -> Path:
        """Where uploaded files wait to be imported (inside the data directory)."""
        return self.paths.dir("uploads")

    def upload(
        self,
        upload: Path,
        activity: str,
        *,
        activity_type: str | None = None,
        arguments: Sequence[ArgumentSpec] = (),
        episode_id: str | None = None,
        max_decompressed_bytes: int = DEFAULT_LIMIT_BYTES,
        max_unpacked_bytes: int = 4 * 1024**3,
    ) -> ImportReport:
        """Import a bag received as the file ``upload``: a ROS 1 ``.bag`` file, or a tar of a
        ROS 2 bag directory (see :func:`episodes.bag_import.import_upload` for the limits).
        Raises :class:`~episodes.errors.InvalidInputError` (field ``body``) for anything else,
        and :class:`~episodes.bag_limits.DamagedBagError` for a bag that cannot be read."""
        what = BagEpisode(activity, activity_type, arguments, episode_id)
        return bag_import.import_upload(
            self.store,
            self.paths,
            upload,
            what,
            now=now(self.clock),
            max_decompressed_bytes=max_decompressed_bytes,
            max_unpacked_bytes=max_unpacked_bytes,
        )
