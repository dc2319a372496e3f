"""Small hostile bags for the hardening tests: compression bombs and damaged ROS 1 records,
written with ``rosbags`` and then patched byte by byte where a field must lie."""

import io
import struct
import tarfile
from pathlib import Path

from rosbags.rosbag1 import Writer as Ros1Writer
from rosbags.rosbag2 import StoragePlugin
from rosbags.rosbag2 import Writer as Ros2Writer
from rosbags.rosbag2.enums import CompressionFormat, CompressionMode
from rosbags.typesys import Stores, get_typestore

__all__ = [
    "patch_mcap_header_length",
    "patch_ros1",
    "ros1_bag",
    "ros2_bag",
    "tar_of",
]

T0 = 1_769_441_400_000_000_000
_STRING = "std_msgs/msg/String"


def ros1_bag(path: Path, *, text_bytes: int, compression: str | None = None) -> Path:
    """A ROS 1 bag with one ``std_msgs/String`` of ``text_bytes`` zeros ('0'), its chunks
    compressed with ``compression`` ("bz2", "lz4" or None)."""
    store = get_typestore(Stores.ROS1_NOETIC)
    writer = Ros1Writer(path)
    if compression is not None:
        writer.set_compression(getattr(Ros1Writer.CompressionFormat, compression.upper()))
    with writer:
        connection = writer.add_connection("/said", _STRING, typestore=store)
        message = store.types[_STRING](data="0" * text_bytes)
        writer.write(connection, T0, store.serialize_ros1(message, _STRING))
    return path


def ros2_bag(
    path: Path,
    *,
    text_bytes: int,
    zstd_messages: bool = False,
    zstd_file: bool = False,
    mcap: bool = False,
) -> Path:
    """A ROS 2 bag directory with one ``std_msgs/String`` of ``text_bytes`` zeros, each message
    compressed with zstd if ``zstd_messages``, the whole storage file if ``zstd_file``; in an
    MCAP file if ``mcap`` (else SQLite)."""
    store = get_typestore(Stores.ROS2_HUMBLE)
    plugin = StoragePlugin.MCAP if mcap else StoragePlugin.SQLITE3
    writer = Ros2Writer(path, version=9, storage_plugin=plugin)
    if zstd_messages:
        writer.set_compression(CompressionMode.MESSAGE, CompressionFormat.ZSTD)
    if zstd_file:
        writer.set_compression(CompressionMode.FILE, CompressionFormat.ZSTD)
    with writer:
        connection = writer.add_connection("/said", _STRING, typestore=store)
        message = store.types[_STRING](data="0" * text_bytes)
        writer.write(connection, T0, store.serialize_cdr(message, _STRING))
    return path


def tar_of(directory: Path, mode: str = "w") -> bytes:
    """``directory`` as a tar (``mode`` "w", "w:gz", "w:xz"...), under its own name."""
    buffer = io.BytesIO()
    with tarfile.open(fileobj=buffer, mode=mode) as tar:
        tar.add(directory, arcname=directory.name)
    return buffer.getvalue()


def _records(data: bytes, start: int, end: int) -> list[tuple[int, dict[str, bytes], int]]:
    """(record offset, header fields, offset of its data length) of the records in
    ``data[start:end]``."""
    found = []
    pos = start
    while pos + 4 <= end:
        (header_len,) = struct.unpack_from("<I", data, pos)
        header, fields = data[pos + 4 : pos + 4 + header_len], {}
        i = 0
        while i < len(header):
            (field_len,) = struct.unpack_from("<I", header, i)
            name, _, value = header[i + 4 : i + 4 + field_len].partition(b"=")
            fields[name.decode()] = value
            i += 4 + field_len
        length_at = pos + 4 + header_len
        (data_len,) = struct.unpack_from("<I", data, length_at)
        found.append((pos, fields, length_at))
        if fields.get("op") == b"\x05" and fields.get("compression") == b"none":
            found += _records(data, length_at + 4, length_at + 4 + data_len)
        pos = length_at + 4 + data_len
    return found


def patch_mcap_header_length(bag: Path, length: int) -> None:
    """Overwrite the length of the first record (the header) of the MCAP file in ``bag``."""
    (path,) = bag.glob("*.mcap")
    data = bytearray(path.read_bytes())
    struct.pack_into("<Q", data, 8 + 1, length)  # after the magic, the opcode
    path.write_bytes(bytes(data))


def patch_ros1(path: Path, op: int, field: str, value: int) -> None:
    """Overwrite, in the first record of kind ``op`` of an uncompressed ROS 1 bag, the 32-bit
    header ``field`` (or with field "data_len", its data length) with ``value``."""
    data = bytearray(path.read_bytes())
    for pos, fields, length_at in _records(bytes(data), 13, len(data)):
        if fields.get("op") != bytes([op]):
            continue
        if field == "data_len":
            struct.pack_into("<I", data, length_at, value)
        else:
            at = data.index(field.encode() + b"=", pos) + len(field) + 1
            struct.pack_into("<I", data, at, value)
        path.write_bytes(bytes(data))
        return
    raise LookupError(f"no record with op {op} in {path}")
