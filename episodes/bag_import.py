"""Bags imported as finished episodes: from a path (inside the data directory, for HTTP
clients) or from uploaded bytes (a ROS 1 ``.bag`` file or a tar of a ROS 2 bag directory).

The samples become the episode's recording (channels mapped, times kept, see
``episodes.streams.import_bag``); the episode begins and ends with the bag's first and last
message and carries an ``imported_from`` annotation and one ``skipped_topic`` annotation per
topic of a type that cannot be imported. The scene memory's state at the time is unknown, so no
snapshots are recorded. Nothing stays behind on failure.
"""

import datetime as dt
import logging
import lzma
import os
import shutil
import struct
import tarfile
import tempfile
import zlib
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

from rosbags.highlevel import AnyReaderError
from rosbags.rosbag1 import ReaderError as Ros1ReaderError
from rosbags.rosbag2 import ReaderError as Ros2ReaderError
from rosbags.serde import SerdeError

from episodes import lifecycle
from episodes.bag_limits import (
    DEFAULT_LIMIT_BYTES,
    DamagedBagError,
    DecompressionLimitError,
    decompression_limit,
)
from episodes.errors import EpisodeStateError, InvalidInputError, NotFoundError
from episodes.lifecycle import ArgumentSpec
from episodes.model import ImportReport, SkippedTopic
from episodes.paths import DataPaths
from episodes.streamlink import descriptors_from_stats
from episodes.streams import import_bag
from episodes.streams.errors import (
    CorruptRecordingError,
    RecordingNotFoundError,
    RecordingStateError,
    StreamError,
)
from episodes.terms import check_id, episode_iri, new_id
from episodes.times import from_ns
from kg import Store

__all__ = [
    "BagEpisode",
    "import_report",
    "import_source",
    "import_upload",
]

log = logging.getLogger(__name__)

MAX_TAR_MEMBERS = 100_000
"""Most members a bag upload's tar may hold."""

# What reading a damaged bag raises, from rosbags and the libraries under it; our own errors
# that are not about the file (an existing destination, say) pass through.
_DAMAGE = (
    CorruptRecordingError,
    DamagedBagError,
    StreamError,
    Ros1ReaderError,
    Ros2ReaderError,
    AnyReaderError,
    SerdeError,
    struct.error,
    ValueError,
    IndexError,
    KeyError,
    TypeError,
    OverflowError,
    EOFError,
    OSError,
    MemoryError,
    AssertionError,
    lzma.LZMAError,
    zlib.error,
)
_NOT_DAMAGE = (RecordingStateError, RecordingNotFoundError, EpisodeStateError)

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
    store: Store,
    paths: DataPaths,
    source: Path | str,
    what: BagEpisode,
    *,
    now: dt.datetime,
    name: str | None = None,
    max_decompressed_bytes: int = DEFAULT_LIMIT_BYTES,
) -> ImportReport:
    """Import the bag at ``source`` as a finished episode; the episode and the topics skipped
    (type and count). ``now`` is the begin of a bag without messages; ``name`` is how messages
    and the ``imported_from`` annotation call the bag (default: ``source``).

    Raises :class:`DamagedBagError` naming the bag and the problem if it cannot be read (a
    compressed piece expanding past ``max_decompressed_bytes``: its subclass
    :class:`DecompressionLimitError`); nothing stays behind then.
    """
    episode_id = check_id(what.episode_id, "id") if what.episode_id is not None else new_id()
    if lifecycle.episode_times(store, episode_iri(episode_id)) is not None:
        raise EpisodeStateError(f"id: an episode {episode_id!r} already exists")
    dest = paths.streams(episode_id)
    shown = name if name is not None else str(source)
    try:
        with decompression_limit(max_decompressed_bytes):
            result = import_bag(source, dest=dest, episode_id=episode_id)
    except BaseException as error:
        shutil.rmtree(dest, ignore_errors=True)
        if isinstance(error, _DAMAGE) and not isinstance(error, _NOT_DAMAGE):
            reason = str(error).replace(str(source), shown) or (
                f"{type(error).__name__}: its records do not fit together"
            )
            kind = DecompressionLimitError if _over_limit(error) else DamagedBagError
            raise kind(f"bag {shown!r}: cannot be imported ({reason})") from None
        raise
    skipped = tuple(
        SkippedTopic(topic, str(info["message_type"]), int(info["count"]))
        for topic, info in sorted(result.skipped.items())
    )
    try:
        start = from_ns(result.start_ns) or now
        lifecycle.begin_episode(
            store,
            activity=what.activity,
            activity_type=what.activity_type,
            arguments=what.arguments,
            begin=start,
            episode_id=episode_id,
            end=from_ns(result.end_ns) or start,
            streams=descriptors_from_stats(result.channels, paths.dir("streams")),
            snapshots=False,
        )
    except BaseException:
        shutil.rmtree(dest, ignore_errors=True)
        raise
    notes = [("imported_from", shown)]
    notes += [("skipped_topic", f"{t.topic} {t.message_type} x{t.count}") for t in skipped]
    for key, value in notes:
        lifecycle.add_annotation(
            store, episode_id, key=key, value=value, created=now, author=IMPORTER
        )
    if skipped:
        log.warning("import %s: skipped %s", episode_id, [t.topic for t in skipped])
    return ImportReport(lifecycle.get_episode(store, episode_id), skipped)


def _over_limit(error: BaseException | None) -> bool:
    """Whether ``error``, or an error it was raised from, is the decompression limit's."""
    seen: set[int] = set()
    while error is not None and id(error) not in seen:
        if isinstance(error, DecompressionLimitError):
            return True
        seen.add(id(error))
        error = error.__cause__ or error.__context__
    return False


def import_source(paths: DataPaths, path: str) -> Path:
    """The bag at ``path`` inside the data directory (relative to it, or absolute inside it).

    What an HTTP client may import: nothing outside the data directory. Raises
    :class:`InvalidInputError` naming the path when it is empty, outside, or neither a ``.bag``
    file nor a ROS 2 bag directory (one with ``metadata.yaml``), :class:`NotFoundError` when
    nothing is there.
    """
    root = paths.dir(".").resolve()
    expected = (
        "a ROS 1 .bag file or a ROS 2 bag directory (with metadata.yaml) inside the "
        "data directory, absolute or relative to it"
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
    store: Store,
    paths: DataPaths,
    upload: Path,
    what: BagEpisode,
    *,
    now: dt.datetime,
    max_decompressed_bytes: int = DEFAULT_LIMIT_BYTES,
    max_unpacked_bytes: int = 4 * 1024**3,
) -> ImportReport:
    """Import a bag received as the file ``upload``: a ROS 1 ``.bag`` file, or a tar
    (optionally compressed) of a ROS 2 bag directory. ``upload`` is left in place.

    A tar is unpacked in a scratch directory under the data directory (removed afterwards),
    one member at a time: its members' declared sizes may add up to ``max_unpacked_bytes``, or
    ``max_decompressed_bytes`` for a compressed tar, and the unpacking stops before the member
    that would pass the limit. Raises :class:`InvalidInputError` (field ``body``) for anything
    else than a bag or a tar of one, or a tar unpacking past its limit;
    :class:`DamagedBagError` for a bag that cannot be read.
    """
    expected = "a ROS 1 .bag file, or a tar archive of one ROS 2 bag directory"
    size = upload.stat().st_size
    if not size:
        raise InvalidInputError("body", "0 bytes", expected)
    with upload.open("rb") as head:
        magic = head.read(13)
    scratch_root = paths.dir("uploads")
    scratch_root.mkdir(parents=True, exist_ok=True)
    scratch = Path(tempfile.mkdtemp(prefix="upload-", dir=scratch_root))
    options = {
        "now": now,
        "name": "the uploaded bag",
        "max_decompressed_bytes": max_decompressed_bytes,
    }
    try:
        if magic.startswith(b"#ROSBAG V2.0"):
            source = scratch / "upload.bag"
            try:
                os.link(upload, source)
            except OSError:
                shutil.copyfile(upload, source)
        else:
            compressed = not _is_plain_tar(upload)
            limit = (
                min(max_unpacked_bytes, max_decompressed_bytes)
                if compressed
                else max_unpacked_bytes
            )
            source = _untar_bag(upload, scratch, expected, limit_bytes=limit)
        return import_report(store, paths, source, what, **options)  # type: ignore[arg-type]
    finally:
        shutil.rmtree(scratch, ignore_errors=True)


def _is_plain_tar(path: Path) -> bool:
    """Whether ``path`` is an uncompressed tar (``ustar`` at offset 257)."""
    with path.open("rb") as file:
        file.seek(257)
        return file.read(5) == b"ustar"


def _untar_bag(upload: Path, scratch: Path, expected: str, *, limit_bytes: int) -> Path:
    """Unpack a tar of one ROS 2 bag directory into ``scratch``, member by member while the
    declared sizes stay within ``limit_bytes``; the bag directory."""
    target = scratch / "bag"
    unpacked = members = 0
    try:
        with tarfile.open(upload, mode="r|*") as archive:
            for member in archive:
                members += 1
                unpacked += max(member.size, 0)
                if unpacked > limit_bytes or members > MAX_TAR_MEMBERS:
                    raise InvalidInputError(
                        "body",
                        f"a tar unpacking to more than {limit_bytes} bytes"
                        if unpacked > limit_bytes
                        else f"a tar of more than {MAX_TAR_MEMBERS} members",
                        f"{expected}, within the upload limits (max_upload_bytes, "
                        "max_decompressed_bytes for a compressed tar)",
                    )
                archive.extract(member, target, filter="data")
    except (tarfile.TarError, OSError, ValueError, EOFError) as error:
        if isinstance(error, InvalidInputError):
            raise
        reason = str(error).replace(str(scratch), "")
        raise InvalidInputError(
            "body", f"{upload.stat().st_size} bytes", f"{expected} ({reason})"
        ) from None
    found = sorted(p.parent for p in target.rglob("metadata.yaml"))
    if len(found) != 1:
        raise InvalidInputError(
            "body", f"a tar with {len(found)} metadata.yaml files", f"{expected} (exactly one)"
        )
    return found[0]
