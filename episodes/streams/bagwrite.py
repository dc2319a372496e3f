"""Writing recordings: one rosbag2 directory (``metadata.yaml`` and one MCAP file).

:class:`BagWriter` is the only code that writes a recording: the recorder, bag export, import
and recovery (through the recorder) and the scene channel's rewrite all use it; the MCAP file
itself is written by :class:`episodes.streams.mcapwrite.McapWriter` (chunk, data-section and
summary CRCs, every index). The file is what ``ros2 bag record`` writes with its MCAP storage:
profile ``ros2``, one ``ros2msg`` schema per message type, CDR messages, each channel's
``offered_qos_profiles`` in its metadata, and a ``rosbag2`` metadata record holding the bag's
metadata; ``metadata.yaml`` beside it lists the topics, counts and times as rosbags' writer
does, so ``rosbags``, ``ros2 bag``, the ``mcap`` package's readers and
:mod:`episodes.streams.mcapread` open it. Messages of ``ALONE_BYTES`` or more (images) get
chunks of their own.

Messages must be written in log-time order (the caller's contract: the recorder's ticks only
move forward, the scene channel's rewrite merges its updates by log time). :meth:`BagWriter.flush`
ends the chunk in progress and hands the file's buffer to the operating system, so a crash
loses only what came after the last flush; such a file has no summary and is read forward.

>>> import tempfile, pathlib
>>> from episodes.streams.messages import typestore
>>> with tempfile.TemporaryDirectory() as tmp:
...     bag = BagWriter(pathlib.Path(tmp) / "ep", typestore=typestore())
...     topic = bag.add_connection("/note", "std_msgs/msg/String")
...     text = typestore().types["std_msgs/msg/String"](data="hello")
...     bag.write(topic, 1_000, typestore().serialize_cdr(text, "std_msgs/msg/String"))
...     bag.close().name, sorted(p.name for p in (pathlib.Path(tmp) / "ep").iterdir())
('ep.mcap', ['ep.mcap', 'metadata.yaml'])
"""

from __future__ import annotations

import os
from collections.abc import Mapping
from dataclasses import dataclass
from importlib.metadata import PackageNotFoundError, version
from io import StringIO
from pathlib import Path
from typing import Any

from mcap.writer import LIBRARY_IDENTIFIER
from rosbags.typesys.store import Typestore
from ruamel.yaml import YAML

from episodes.streams.errors import InvalidSampleError, RecordingStateError
from episodes.streams.mcapwrite import CHUNK_BYTES, COMPRESSIONS, McapWriter

__all__ = ["ALONE_BYTES", "BagWriter", "bag_metadata_text", "mcap_file"]

ROSBAG2_VERSION = 9
ALONE_BYTES = 64 * 1024
"""A recording's messages at least this large (images) get chunks of their own, so a reader
of other channels (a plot of the joints, replay of some channels from object storage) skips
them without reading them."""
_NO_QOS = "[]"
"""``offered_qos_profiles`` of a channel with none, as rosbag2 version 9 writes it."""


def mcap_file(path: Path) -> Path:
    """The MCAP file inside a rosbag2 directory written by :class:`BagWriter`."""
    return path / f"{path.name}.mcap"


def _library() -> str:
    try:
        ours = version("engram-kg")
    except PackageNotFoundError:  # run from a source tree that was never installed
        ours = "0"
    return f"engram-{ours}; {LIBRARY_IDENTIFIER}"


@dataclass
class _Topic:
    channel: int
    topic: str
    msgtype: str
    type_hash: str
    count: int = 0


class BagWriter:
    """Writes one new rosbag2 directory ``path`` holding ``<path.name>.mcap`` and
    ``metadata.yaml`` (the latter on :meth:`close`).

    Args:
        path: the bag directory to create; it must not exist yet.
        typestore: where message definitions and type hashes come from.
        compression: ``None``, ``"zstd"`` or ``"lz4"``: how chunks are compressed.
        custom_data: string pairs stored in ``metadata.yaml``'s ``custom_data``.
        chunk_bytes: a chunk closes once its records pass this size.
        alone_bytes: messages at least this large get chunks of their own.

    Raises:
        RecordingStateError: ``path`` exists already.
        InvalidSampleError: an unknown compression.
    """

    def __init__(
        self,
        path: Path | str,
        *,
        typestore: Typestore,
        compression: str | None = None,
        custom_data: Mapping[str, str] | None = None,
        chunk_bytes: int = CHUNK_BYTES,
        alone_bytes: int | None = ALONE_BYTES,
    ) -> None:
        if compression not in COMPRESSIONS:
            raise InvalidSampleError("compression", compression, "None, 'zstd' or 'lz4'")
        self.path = Path(path)
        self.compression = compression
        self._typestore = typestore
        self._custom_data = dict(custom_data or {})
        try:
            self.path.mkdir(parents=True)
        except FileExistsError:
            raise RecordingStateError(f"path: {str(self.path)!r} exists already") from None
        self.file = mcap_file(self.path)
        self._stream = self.file.open("xb")
        self._mcap = McapWriter(
            self._stream,
            compression=compression,
            chunk_bytes=chunk_bytes,
            alone_bytes=alone_bytes,
            profile="ros2",
            library=_library(),
        )
        self._schemas: dict[str, int] = {}
        self._topics: dict[int, _Topic] = {}
        self._start_ns: int | None = None
        self._end_ns = 0
        self._closed = False

    def add_connection(
        self,
        topic: str,
        msgtype: str,
        *,
        definition: tuple[str, str] | None = None,
        type_hash: str | None = None,
    ) -> int:
        """Declare a topic of ROS 2 type ``msgtype``; return the id its messages are written to.

        ``definition`` (schema encoding, text) and ``type_hash`` (RIHS01) default to what the
        type store generates; a copy passes those of the file it copies.

        Raises:
            RecordingStateError: the topic is declared already, or the bag is closed.
        """
        self._check_open()
        if any(t.topic == topic for t in self._topics.values()):
            raise RecordingStateError(f"topic: {topic!r} is declared already")
        schema = self._schemas.get(msgtype)
        if schema is None:
            if definition is None:
                text, _ = self._typestore.generate_msgdef(msgtype, ros_version=2)
                definition = ("ros2msg", text)
            encoding, text = definition
            schema = self._mcap.register_schema(msgtype, encoding, text.encode())
            self._schemas[msgtype] = schema
        channel = self._mcap.register_channel(
            topic, "cdr", schema, {"offered_qos_profiles": _NO_QOS}
        )
        self._topics[channel] = _Topic(
            channel, topic, msgtype, type_hash or self._typestore.hash_rihs01(msgtype)
        )
        return channel

    def write(self, channel: int, time_ns: int, data: bytes | memoryview) -> None:
        """Write one serialised message at log (and publish) time ``time_ns``.

        Raises:
            KeyError: ``channel`` was not returned by :meth:`add_connection`.
        """
        self._topics[channel].count += 1
        if self._start_ns is None:
            self._start_ns = time_ns
        self._start_ns = min(self._start_ns, time_ns)
        self._end_ns = max(self._end_ns, time_ns)
        self._mcap.add_message(channel, time_ns, data, time_ns)

    def add_metadata(self, name: str, values: Mapping[str, str]) -> None:
        """Write a metadata record (a copy keeps those of the file it copies)."""
        self._check_open()
        self._mcap.add_metadata(name, dict(values))

    def flush(self, *, fsync: bool = False) -> None:
        """End the chunk in progress and pass everything written to the operating system
        (with ``fsync``, to the disk)."""
        self._mcap.flush()
        if fsync:
            os.fsync(self._stream.fileno())

    def pass_on(self) -> None:
        """Pass chunks the library has completed to the operating system, leaving the chunk in
        progress open (cheap when there are none: a buffered write that is empty)."""
        self._stream.flush()

    @property
    def message_count(self) -> int:
        """Messages written so far."""
        return sum(t.count for t in self._topics.values())

    def close(self) -> Path:
        """Complete the MCAP file (summary, footer) and write ``metadata.yaml``; return the file.

        Raises:
            RecordingStateError: closed already.
        """
        self._check_open()
        self._closed = True
        info = self._info()
        self._mcap.flush()  # the last chunk before the record
        self._mcap.add_metadata("rosbag2", {"serialized_metadata": bag_metadata_text(info).strip()})
        self._mcap.finish()
        self._stream.flush()
        os.fsync(self._stream.fileno())
        self._stream.close()
        metadata = self.path / "metadata.yaml"
        partial = metadata.with_name("metadata.yaml.part")
        partial.write_text(bag_metadata_text({"rosbag2_bagfile_information": info}), "utf8")
        partial.replace(metadata)
        return self.file

    def abort(self) -> None:
        """Close the file without its summary (a crash's file: read forward, ``recover``)."""
        if not self._closed:
            self._closed = True
            self._stream.close()

    def _check_open(self) -> None:
        if self._closed:
            raise RecordingStateError(f"the bag {str(self.path)!r} is closed")

    def _info(self) -> dict[str, Any]:
        """The bag's metadata, as rosbags' writer (version 9) lays it out."""
        start = self._start_ns if self._start_ns is not None else 2**63 - 1
        duration = max(0, self._end_ns - start)
        count = self.message_count
        return {
            "version": ROSBAG2_VERSION,
            "storage_identifier": "mcap",
            "relative_file_paths": [self.file.name],
            "duration": {"nanoseconds": duration},
            "starting_time": {"nanoseconds_since_epoch": start},
            "message_count": count,
            "topics_with_message_count": [
                {
                    "topic_metadata": {
                        "name": t.topic,
                        "type": t.msgtype,
                        "serialization_format": "cdr",
                        "offered_qos_profiles": [],
                        "type_description_hash": t.type_hash,
                    },
                    "message_count": t.count,
                }
                for t in self._topics.values()
            ],
            "compression_format": "",
            "compression_mode": "",
            "files": [
                {
                    "path": self.file.name,
                    "starting_time": {"nanoseconds_since_epoch": start},
                    "duration": {"nanoseconds": duration},
                    "message_count": count,
                }
            ],
            "custom_data": self._custom_data or None,
            "ros_distro": "rosbags",
        }


def bag_metadata_text(document: Mapping[str, Any]) -> str:
    """``document`` as the YAML text of a rosbag2 ``metadata.yaml`` (block style)."""
    yaml = YAML(typ="safe")
    yaml.default_flow_style = False
    text = StringIO()
    yaml.dump(dict(document), text)
    return text.getvalue()
