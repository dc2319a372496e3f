"""Bags imported as finished episodes: from a path (inside the data directory, for HTTP
clients) or from uploaded bytes (a ROS 1 ``.bag`` file or a tar of a ROS 2 bag directory).

The samples become the episode's recording (channels mapped, times kept, see
``episodes.streams.import_bag``); the episode begins and ends with the bag's first and last
message and carries an ``imported_from`` annotation and one ``skipped_topic`` annotation per
topic of a type that cannot be imported. The scene memory's state at the time is unknown, so no
snapshots are recorded. Nothing stays behind on failure.
"""

import datetime as dt
import io
import logging
import shutil
import tarfile
import tempfile
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

from episodes import lifecycle
from episodes.errors import EpisodeStateError, InvalidInputError, NotFoundError
from episodes.lifecycle import ArgumentSpec
from episodes.model import ImportReport, SkippedTopic
from episodes.paths import DataPaths
from episodes.streamlink import descriptors_from_stats
from episodes.streams import import_bag
from episodes.terms import check_id, episode_iri, new_id
from kg import Store

__all__ = ["BagEpisode", "import_report", "import_source", "import_upload"]

log = logging.getLogger(__name__)

IMPORTER = "engram import"
"""The author of the annotations an import writes."""


@dataclass(frozen=True)
class BagEpisode:
    """What the imported episode is: its activity, type, arguments and id (new by default)."""

    activity: str
    activity_type: str | None = None
    arguments: Sequence[ArgumentSpec] = ()
    episode_id: str | None = None


def import_report(
    store: Store, paths: DataPaths, source: Path | str, what: BagEpisode, *, now: dt.datetime
) -> ImportReport:
    """Import the bag at ``source`` as a finished episode; the episode and the topics skipped
    (type and count). ``now`` is the begin of a bag without messages."""
    episode_id = check_id(what.episode_id, "id") if what.episode_id is not None else new_id()
    if lifecycle.episode_times(store, episode_iri(episode_id)) is not None:
        raise EpisodeStateError(f"id: an episode {episode_id!r} already exists")
    dest = paths.streams(episode_id)
    result = import_bag(source, dest=dest, episode_id=episode_id)
    skipped = tuple(
        SkippedTopic(topic, str(info["message_type"]), int(info["count"]))
        for topic, info in sorted(result.skipped.items())
    )
    try:
        start = _from_ns(result.start_ns) or now
        lifecycle.begin_episode(
            store,
            activity=what.activity,
            activity_type=what.activity_type,
            arguments=what.arguments,
            begin=start,
            episode_id=episode_id,
            end=_from_ns(result.end_ns) or start,
            streams=descriptors_from_stats(result.channels, paths.dir("streams")),
            snapshots=False,
        )
    except BaseException:
        shutil.rmtree(dest, ignore_errors=True)
        raise
    notes = [("imported_from", str(source))]
    notes += [("skipped_topic", f"{t.topic} {t.message_type} x{t.count}") for t in skipped]
    for key, value in notes:
        lifecycle.add_annotation(
            store, episode_id, key=key, value=value, created=now, author=IMPORTER
        )
    if skipped:
        log.warning("import %s: skipped %s", episode_id, [t.topic for t in skipped])
    return ImportReport(lifecycle.get_episode(store, episode_id), skipped)


def import_source(paths: DataPaths, path: str) -> Path:
    """The bag at ``path`` inside the data directory (relative to it, or absolute inside it).

    What an HTTP client may import: nothing outside the data directory. Raises
    :class:`InvalidInputError` naming the path when it is empty, outside, or neither a ``.bag``
    file nor a ROS 2 bag directory (one with ``metadata.yaml``), :class:`NotFoundError` when
    nothing is there.
    """
    root = paths.dir(".").resolve()
    expected = (
        f"a ROS 1 .bag file or a ROS 2 bag directory (with metadata.yaml) inside the "
        f"data directory {str(root)!r}, absolute or relative to it"
    )
    if not isinstance(path, str) or not path.strip() or "\x00" in path:
        raise InvalidInputError("path", path, expected)
    candidate = (root / path).resolve()
    if not candidate.is_relative_to(root) or candidate == root:
        raise InvalidInputError("path", path, expected)
    if candidate.is_file() and candidate.suffix == ".bag":
        return candidate
    if candidate.is_dir() and (candidate / "metadata.yaml").is_file():
        return candidate
    if not candidate.exists():
        raise NotFoundError(f"path: nothing at {path!r} in the data directory")
    raise InvalidInputError("path", path, expected)


def import_upload(
    store: Store, paths: DataPaths, data: bytes, what: BagEpisode, *, now: dt.datetime
) -> ImportReport:
    """Import a bag sent as bytes: a ROS 1 ``.bag`` file, or a tar of a ROS 2 bag directory.

    The upload is unpacked in a scratch directory under the data directory and removed
    afterwards. Raises :class:`InvalidInputError` (field ``body``) for anything else.
    """
    expected = "a ROS 1 .bag file, or a tar archive of one ROS 2 bag directory"
    if not data:
        raise InvalidInputError("body", "0 bytes", expected)
    scratch_root = paths.dir("uploads")
    scratch_root.mkdir(parents=True, exist_ok=True)
    scratch = Path(tempfile.mkdtemp(prefix="upload-", dir=scratch_root))
    try:
        if data.startswith(b"#ROSBAG V2.0"):
            source = scratch / "upload.bag"
            source.write_bytes(data)
        else:
            source = _untar_bag(data, scratch, expected)
        return import_report(store, paths, source, what, now=now)
    finally:
        shutil.rmtree(scratch, ignore_errors=True)


def _untar_bag(data: bytes, scratch: Path, expected: str) -> Path:
    """Unpack a tar of one ROS 2 bag directory into ``scratch``; the bag directory."""
    try:
        with tarfile.open(fileobj=io.BytesIO(data)) as archive:
            archive.extractall(scratch / "bag", filter="data")
    except (tarfile.TarError, OSError, ValueError) as error:
        raise InvalidInputError("body", f"{len(data)} bytes", f"{expected} ({error})") from None
    found = sorted(p.parent for p in (scratch / "bag").rglob("metadata.yaml"))
    if len(found) != 1:
        raise InvalidInputError(
            "body", f"a tar with {len(found)} metadata.yaml files", f"{expected} (exactly one)"
        )
    return found[0]


def _from_ns(ns: int | None) -> dt.datetime | None:
    return None if ns is None else dt.datetime.fromtimestamp(ns / 1e9, dt.UTC)
