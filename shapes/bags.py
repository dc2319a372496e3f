"""ROS 1 and ROS 2 bags of ``sensor_msgs/PointCloud2``, read and written with ``rosbags``.

Reading decodes x, y, z (any float or integer type, either endianness, padded rows) and, when
present, the packed ``rgb`` / ``rgba`` field; points with a non-finite coordinate are dropped.
Writing exists so that tests and demos can make real bags from synthetic frames.
"""

from __future__ import annotations

import logging
from collections.abc import Iterable, Iterator
from pathlib import Path
from typing import Any, Literal

import numpy as np
import numpy.typing as npt

from shapes.errors import ShapesError, SourceError
from shapes.frame import Frame
from shapes.types import FloatArray

__all__ = ["POINTCLOUD2", "bag_message_count", "read_bag", "write_bag"]

log = logging.getLogger(__name__)

POINTCLOUD2 = "sensor_msgs/msg/PointCloud2"
# PointField datatypes -> numpy type codes.
_DATATYPES = {1: "i1", 2: "u1", 3: "i2", 4: "u2", 5: "i4", 6: "u4", 7: "f4", 8: "f8"}


def _bag_paths(path: Path) -> list[Path]:
    if not path.exists():
        raise SourceError(f"bag: {str(path)!r} does not exist")
    if path.is_file() and path.suffix in {".mcap", ".db3"}:
        return [path.parent]  # a ROS 2 bag is its directory (with metadata.yaml)
    return [path]


def decode_pointcloud2(msg: Any) -> tuple[FloatArray, FloatArray | None]:
    """Points ``(N, 3)`` and colours ``(N, 3)`` in [0, 1] (or None) of one PointCloud2 message.

    Raises SourceError if the message has no x, y, z fields or its data is too short.
    """
    points, colours, _ = decode_pointcloud2_pixels(msg)
    return points, colours


def decode_pointcloud2_pixels(
    msg: Any,
) -> tuple[FloatArray, FloatArray | None, npt.NDArray[np.intp]]:
    """:func:`decode_pointcloud2`, and the flat row-major pixel of each point kept (what an
    organised cloud's :class:`~shapes.frame.Frame` carries). ``msg.data`` may be a sequence of
    bytes (rosbags) or ``bytes`` (rospy).
    """
    endian = ">" if msg.is_bigendian else "<"
    fields = {f.name: f for f in msg.fields}
    missing = [n for n in ("x", "y", "z") if n not in fields]
    if missing:
        raise SourceError(
            f"PointCloud2.fields: expected x, y and z, got {sorted(fields)} (missing {missing})"
        )
    names, formats, offsets = [], [], []
    for name in ("x", "y", "z", "rgb", "rgba"):
        if name in fields:
            f = fields[name]
            if f.datatype not in _DATATYPES:
                raise SourceError(
                    f"PointCloud2.fields[{name!r}].datatype: expected 1..8, got {f.datatype}"
                )
            code = "u4" if name in ("rgb", "rgba") else _DATATYPES[f.datatype]
            names.append(name)
            formats.append(endian + code)
            offsets.append(f.offset)
    dtype = np.dtype(
        {"names": names, "formats": formats, "offsets": offsets, "itemsize": msg.point_step}
    )
    n = int(msg.width) * int(msg.height)
    data = msg.data
    raw = (
        np.frombuffer(data, dtype=np.uint8)
        if isinstance(data, bytes | bytearray | memoryview)
        else np.asarray(data, dtype=np.uint8)
    )
    row_bytes = int(msg.width) * int(msg.point_step)
    if raw.size < int(msg.row_step) * (int(msg.height) - 1) + row_bytes:
        raise SourceError(
            f"PointCloud2.data: expected at least {int(msg.row_step) * int(msg.height)} bytes "
            f"for {msg.height} rows, got {raw.size}"
        )
    if int(msg.row_step) != row_bytes:
        raw = np.concatenate(
            [
                raw[r * int(msg.row_step) : r * int(msg.row_step) + row_bytes]
                for r in range(int(msg.height))
            ]
        )
    rec = np.frombuffer(raw, dtype=dtype, count=n)  # a view: no copy of the cloud's bytes
    points = np.empty((n, 3))
    for column, axis in enumerate("xyz"):
        points[:, column] = rec[axis]
    colours = None
    colour_field = "rgb" if "rgb" in names else "rgba" if "rgba" in names else None
    if colour_field is not None:
        packed = rec[colour_field].astype(np.uint32)
        colours = np.column_stack(((packed >> 16) & 255, (packed >> 8) & 255, packed & 255))
        colours = colours.astype(np.float64) / 255.0
    ok = np.isfinite(points[:, 0]) & np.isfinite(points[:, 1]) & np.isfinite(points[:, 2])
    return points[ok], None if colours is None else colours[ok], np.flatnonzero(ok)


def _connections(reader: Any, topic: str | None, path: Path) -> list[Any]:
    conns = [c for c in reader.connections if c.msgtype == POINTCLOUD2]
    if topic is not None:
        conns = [c for c in conns if c.topic == topic]
    if not conns:
        topics = sorted({f"{c.topic} ({c.msgtype})" for c in reader.connections})
        wanted = f"topic {topic!r} of type" if topic else "a topic of type"
        raise SourceError(f"bag {str(path)!r}: expected {wanted} {POINTCLOUD2}, got {topics}")
    return conns


def _reader(path: Path) -> Any:
    from rosbags.highlevel import AnyReader
    from rosbags.typesys import Stores, get_typestore

    try:
        reader = AnyReader(_bag_paths(path), default_typestore=get_typestore(Stores.ROS2_HUMBLE))
        reader.open()
    except SourceError:
        raise
    except Exception as exc:  # rosbags raises its own reader errors
        raise SourceError(f"bag {str(path)!r}: cannot be read ({exc})") from exc
    return reader


def _messages(reader: Any, connections: list[Any], path: Path) -> Iterator[Any]:
    """``reader.messages``, a damaged record raised as SourceError naming the bag."""
    messages = reader.messages(connections=connections)
    while True:
        try:
            item = next(messages)
        except StopIteration:
            return
        except (ShapesError, ValueError):  # ours, and a bound the reader was given
            raise
        except Exception as exc:  # rosbags' reader errors, struct and assertion errors
            problem = str(exc) or f"{type(exc).__name__}: its records do not fit together"
            raise SourceError(f"bag {str(path)!r}: cannot be read ({problem})") from None
        yield item


def bag_message_count(path: str | Path, topic: str | None = None) -> int:
    """How many PointCloud2 messages ``read_bag`` would go through (for a progress bar)."""
    reader = _reader(Path(path))
    try:
        return sum(c.msgcount for c in _connections(reader, topic, Path(path)))
    finally:
        reader.close()


def read_bag(
    path: str | Path,
    *,
    topic: str | None = None,
    world_from_sensor: FloatArray | None = None,
) -> Iterator[Frame]:
    """Frames from the PointCloud2 messages of a ROS 1 ``.bag`` or a ROS 2 bag directory.

    ``topic`` picks one topic (default: every PointCloud2 topic). Messages with no finite point
    are skipped (logged). Raises SourceError if the bag is missing, unreadable, or has no
    PointCloud2 topic (the message lists the topics it has).
    """
    p = Path(path)
    reader = _reader(p)
    pose = np.eye(4) if world_from_sensor is None else world_from_sensor
    try:
        for conn, timestamp, raw in _messages(reader, _connections(reader, topic, p), p):
            msg = reader.deserialize(raw, conn.msgtype)
            points, colours = decode_pointcloud2(msg)
            if len(points) == 0:
                log.info("skipping an empty cloud at %d ns on %s", timestamp, conn.topic)
                continue
            stamp = msg.header.stamp.sec + msg.header.stamp.nanosec * 1e-9
            yield Frame(points, colours, stamp, msg.header.frame_id, pose)
    finally:
        reader.close()


def _message(ts: Any, frame: Frame, stamp: float) -> Any:
    t = ts.types
    n = len(frame.points)
    fields = [t["sensor_msgs/msg/PointField"](name, 4 * i, 7, 1) for i, name in enumerate("xyz")]
    step = 12
    data = np.zeros((n, 4 if frame.colours is not None else 3), dtype="<f4")
    data[:, :3] = frame.points
    if frame.colours is not None:
        rgb = np.round(frame.colours * 255).astype(np.uint32)
        data[:, 3] = ((rgb[:, 0] << 16) | (rgb[:, 1] << 8) | rgb[:, 2]).view("<f4")
        fields.append(t["sensor_msgs/msg/PointField"]("rgb", 12, 7, 1))
        step = 16
    sec = int(stamp)
    time = t["builtin_interfaces/msg/Time"](sec, round((stamp - sec) * 1e9))
    header_cls = t["std_msgs/msg/Header"]
    if "seq" in header_cls.__dataclass_fields__:
        header = header_cls(0, time, frame.frame_id)
    else:
        header = header_cls(time, frame.frame_id)
    return t[POINTCLOUD2](
        header, 1, n, fields, False, step, step * n, data.view(np.uint8).ravel(), True
    )


def write_bag(
    path: str | Path,
    frames: Iterable[Frame],
    *,
    ros: Literal[1, 2] = 2,
    topic: str = "/camera/depth/points",
) -> int:
    """Write frames (sensor-frame points, colours as packed ``rgb``) as PointCloud2 messages.

    ROS 1 writes one ``.bag`` file, ROS 2 a bag directory (SQLite storage). A frame without a
    stamp gets its index in seconds. Returns the number of messages written.
    """
    from rosbags.rosbag1 import Writer as Writer1
    from rosbags.rosbag2 import Writer as Writer2
    from rosbags.typesys import Stores, get_typestore

    count = 0
    if ros == 1:
        ts = get_typestore(Stores.ROS1_NOETIC)
        with Writer1(Path(path)) as w1:
            conn = w1.add_connection(topic, POINTCLOUD2, typestore=ts)
            for i, frame in enumerate(frames):
                stamp = float(i) if frame.stamp is None else frame.stamp
                w1.write(
                    conn,
                    int(stamp * 1e9),
                    ts.serialize_ros1(_message(ts, frame, stamp), POINTCLOUD2),
                )
                count += 1
        return count
    ts = get_typestore(Stores.ROS2_HUMBLE)
    with Writer2(Path(path), version=9) as w2:
        conn = w2.add_connection(topic, POINTCLOUD2, typestore=ts)
        for i, frame in enumerate(frames):
            stamp = float(i) if frame.stamp is None else frame.stamp
            w2.write(
                conn, int(stamp * 1e9), ts.serialize_cdr(_message(ts, frame, stamp), POINTCLOUD2)
            )
            count += 1
    return count
