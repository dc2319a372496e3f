"""Stored scenes as Foxglove ``SceneUpdate`` messages, inside an episode's rosbag2 recording.

Each scene becomes one ``SceneEntity`` (id: the scene's name) whose primitives are Foxglove
spheres, cylinders (a cone is a cylinder with ``top_scale`` 0) and cubes (a plane is a thin
square across its normal), at the stored centres, sizes, axes and colours, with a text label per
primitive; frame ``world``, x right, y behind, z up, metres.

The channel ``/engram/scenes`` is written into the episode's own MCAP file as the ROS 2 type
``foxglove_msgs/msg/SceneUpdate`` (CDR, its ``.msg`` definitions registered in the ``rosbags``
type store and stored in the file as a ``ros2msg`` schema). So the bag stays a valid rosbag2
recording that ``rosbags`` and ``ros2 bag`` read, the ``mcap`` library reads the scene channel,
and Foxglove and Lichtblick draw it in their 3D panel (they decode ROS 2 messages by the
schema the file carries). A ``jsonschema`` channel, Foxglove's other encoding, would make
``rosbags`` refuse the file.

:func:`add_scene_channel` adds the channel to a closed recording (a copy written through
:class:`episodes.streams.bagwrite.BagWriter`, the recorder's own writer, with the updates
placed among the messages in log-time order), or creates a recording holding only the scenes
when the episode recorded no streams. Pure files, no RDF: :mod:`episodes.scene_channel` reads
the scenes from the graph.

>>> from kg.primitive import Primitive
>>> ball = Primitive("ball", "Sphere", centre=(0.1, 0.0, 0.05), radius=0.05)
>>> entity = scene_entity("experience-1", [ball], time_ns=1_500_000_000)
>>> entity["spheres"][0]["size"], entity["timestamp"]
({'x': 0.1, 'y': 0.1, 'z': 0.1}, {'sec': 1, 'nsec': 500000000})
"""

import json
import logging
import math
import os
import shutil
from collections.abc import Iterable, Mapping, Sequence
from functools import lru_cache
from pathlib import Path
from typing import Any

from mcap.records import Attachment, Channel, Message, Metadata, Schema
from rosbags.typesys import Stores, get_types_from_msg, get_typestore
from rosbags.typesys.store import Typestore
from ruamel.yaml import YAML

from episodes.streams.bagwrite import BagWriter, mcap_file
from episodes.streams.errors import CorruptRecordingError
from episodes.streams.mcapread import McapFile
from episodes.streams.tick_writer import FORMAT_VERSION, RECORDING_TOPIC
from kg.primitive import Primitive

__all__ = [
    "SCENE_TOPIC",
    "SCENE_TYPE",
    "add_scene_channel",
    "scene_entity",
    "scene_message",
    "scene_typestore",
]

log = logging.getLogger(__name__)

SCENE_TYPE = "foxglove_msgs/msg/SceneUpdate"
SCENE_TOPIC = "/engram/scenes"
FRAME_ID = "world"
PLANE_SIZE_M = 0.6
PLANE_THICKNESS_M = 0.002
_DEFAULT_COLOURS = {
    "Sphere": (0.98, 0.66, 0.15),
    "Cylinder": (0.08, 0.4, 0.75),
    "Cone": (0.78, 0.16, 0.16),
    "Plane": (0.62, 0.62, 0.62),
}

_POSE = "geometry_msgs/Pose pose\n"
_COLOR = "foxglove_msgs/Color color\n"
FOXGLOVE_DEFINITIONS: dict[str, str] = {
    "foxglove_msgs/msg/Color": "float64 r\nfloat64 g\nfloat64 b\nfloat64 a\n",
    "foxglove_msgs/msg/KeyValuePair": "string key\nstring value\n",
    "foxglove_msgs/msg/ArrowPrimitive": _POSE
    + "float64 shaft_length\nfloat64 shaft_diameter\nfloat64 head_length\n"
    + "float64 head_diameter\n"
    + _COLOR,
    "foxglove_msgs/msg/CubePrimitive": _POSE + "geometry_msgs/Vector3 size\n" + _COLOR,
    "foxglove_msgs/msg/SpherePrimitive": _POSE + "geometry_msgs/Vector3 size\n" + _COLOR,
    "foxglove_msgs/msg/CylinderPrimitive": _POSE
    + "geometry_msgs/Vector3 size\nfloat64 bottom_scale\nfloat64 top_scale\n"
    + _COLOR,
    "foxglove_msgs/msg/LinePrimitive": "uint8 LINE_STRIP=0\nuint8 LINE_LOOP=1\nuint8 LINE_LIST=2\n"
    + "uint8 type\n"
    + _POSE
    + "float64 thickness\nbool scale_invariant\ngeometry_msgs/Point[] points\n"
    + _COLOR
    + "foxglove_msgs/Color[] colors\nuint32[] indices\n",
    "foxglove_msgs/msg/TriangleListPrimitive": _POSE
    + "geometry_msgs/Point[] points\n"
    + _COLOR
    + "foxglove_msgs/Color[] colors\nuint32[] indices\n",
    "foxglove_msgs/msg/TextPrimitive": _POSE
    + "bool billboard\nfloat64 font_size\nbool scale_invariant\n"
    + _COLOR
    + "string text\n",
    "foxglove_msgs/msg/ModelPrimitive": _POSE
    + "geometry_msgs/Vector3 scale\n"
    + _COLOR
    + "bool override_color\nstring url\nstring media_type\nuint8[] data\n",
    "foxglove_msgs/msg/SceneEntityDeletion": "uint8 MATCHING_ID=0\nuint8 ALL=1\n"
    + "builtin_interfaces/Time timestamp\nuint8 type\nstring id\n",
    "foxglove_msgs/msg/SceneEntity": "builtin_interfaces/Time timestamp\nstring frame_id\n"
    + "string id\nbuiltin_interfaces/Duration lifetime\nbool frame_locked\n"
    + "foxglove_msgs/KeyValuePair[] metadata\nfoxglove_msgs/ArrowPrimitive[] arrows\n"
    + "foxglove_msgs/CubePrimitive[] cubes\nfoxglove_msgs/SpherePrimitive[] spheres\n"
    + "foxglove_msgs/CylinderPrimitive[] cylinders\nfoxglove_msgs/LinePrimitive[] lines\n"
    + "foxglove_msgs/TriangleListPrimitive[] triangles\n"
    + "foxglove_msgs/TextPrimitive[] texts\nfoxglove_msgs/ModelPrimitive[] models\n",
    SCENE_TYPE: "foxglove_msgs/SceneEntityDeletion[] deletions\n"
    + "foxglove_msgs/SceneEntity[] entities\n",
}
"""The ROS 2 message definitions of Foxglove's ``foxglove_msgs`` scene types (fields in
Foxglove's order, so the CDR bytes match what Foxglove's own ROS 2 package writes)."""


@lru_cache(maxsize=1)
def scene_typestore() -> Typestore:
    """The ROS 2 (Jazzy) type store with the ``foxglove_msgs`` scene types registered."""
    store = get_typestore(Stores.ROS2_JAZZY)
    for name, text in FOXGLOVE_DEFINITIONS.items():
        store.register(get_types_from_msg(text, name))
    return store


def _vector(v: Sequence[float]) -> dict[str, float]:
    return {"x": float(v[0]), "y": float(v[1]), "z": float(v[2])}


def _rotation_from_z(axis: Sequence[float] | None) -> dict[str, float]:
    """The unit quaternion turning +z onto ``axis`` (Foxglove's cylinders stand along z)."""
    if axis is None:
        return {"x": 0.0, "y": 0.0, "z": 0.0, "w": 1.0}
    norm = math.sqrt(sum(a * a for a in axis)) or 1.0
    x, y, z = (a / norm for a in axis)
    if z < -0.999999:  # opposite: half a turn about x
        return {"x": 1.0, "y": 0.0, "z": 0.0, "w": 0.0}
    # q = (cross(z, a), 1 + dot(z, a)), normalised
    qx, qy, qz, qw = -y, x, 0.0, 1.0 + z
    n = math.sqrt(qx * qx + qy * qy + qz * qz + qw * qw)
    return {"x": qx / n, "y": qy / n, "z": qz / n, "w": qw / n}


def _colour(primitive: Primitive) -> dict[str, float]:
    r, g, b = primitive.colour or _DEFAULT_COLOURS[primitive.kind]
    return {"r": float(r), "g": float(g), "b": float(b), "a": 1.0}


def _time(time_ns: int) -> dict[str, int]:
    return {"sec": time_ns // 1_000_000_000, "nsec": time_ns % 1_000_000_000}


def scene_entity(scene_id: str, primitives: Iterable[Primitive], *, time_ns: int) -> dict[str, Any]:
    """One ``SceneEntity`` drawing ``primitives`` (a sphere, cylinder or cone of their radius,
    5 cm when they have none, and height, their diameter when they have none)."""
    spheres, cylinders, cubes, texts = [], [], [], []
    for p in primitives:
        radius = p.radius or 0.05
        height = p.height or 2 * radius
        pose = {"position": _vector(p.centre), "orientation": _rotation_from_z(p.axis)}
        colour = _colour(p)
        kind = p.kind
        if kind == "Sphere":
            spheres.append({"pose": pose, "size": _vector((2 * radius,) * 3), "color": colour})
        elif kind in ("Cylinder", "Cone"):
            cylinders.append(
                {
                    "pose": pose,
                    "size": _vector((2 * radius, 2 * radius, height)),
                    "bottom_scale": 1.0,
                    "top_scale": 0.0 if kind == "Cone" else 1.0,
                    "color": colour,
                }
            )
        else:
            size = (PLANE_SIZE_M, PLANE_SIZE_M, PLANE_THICKNESS_M)
            cubes.append({"pose": pose, "size": _vector(size), "color": colour})
        label_at = dict(pose, position=_vector((p.centre[0], p.centre[1], p.centre[2] + 0.02)))
        texts.append(
            {
                "pose": label_at,
                "billboard": True,
                "font_size": 12.0,
                "scale_invariant": True,
                "color": {"r": 0.1, "g": 0.1, "b": 0.1, "a": 1.0},
                "text": p.id,
            }
        )
    return {
        "timestamp": _time(time_ns),
        "frame_id": FRAME_ID,
        "id": scene_id,
        "lifetime": {"sec": 0, "nsec": 0},
        "frame_locked": False,
        "metadata": [{"key": "scene", "value": scene_id}],
        "arrows": [],
        "cubes": cubes,
        "spheres": spheres,
        "cylinders": cylinders,
        "lines": [],
        "triangles": [],
        "texts": texts,
        "models": [],
    }


def scene_message(entity: Mapping[str, Any]) -> bytes:
    """A ``SceneUpdate`` replacing what was shown by ``entity`` (a :func:`scene_entity`), CDR."""
    store = scene_typestore()
    types = store.types

    def vector(v: Mapping[str, float], name: str = "Vector3") -> Any:
        return types[f"geometry_msgs/msg/{name}"](x=v["x"], y=v["y"], z=v["z"])

    def pose(p: Mapping[str, Any]) -> Any:
        q = p["orientation"]
        return types["geometry_msgs/msg/Pose"](
            position=vector(p["position"], "Point"),
            orientation=types["geometry_msgs/msg/Quaternion"](
                x=q["x"], y=q["y"], z=q["z"], w=q["w"]
            ),
        )

    def colour(c: Mapping[str, float]) -> Any:
        return types["foxglove_msgs/msg/Color"](r=c["r"], g=c["g"], b=c["b"], a=c["a"])

    def shape(kind: str, s: Mapping[str, Any]) -> Any:
        return types[f"foxglove_msgs/msg/{kind}Primitive"](
            pose=pose(s["pose"]), size=vector(s["size"]), color=colour(s["color"])
        )

    cylinders = [
        types["foxglove_msgs/msg/CylinderPrimitive"](
            pose=pose(c["pose"]),
            size=vector(c["size"]),
            bottom_scale=c["bottom_scale"],
            top_scale=c["top_scale"],
            color=colour(c["color"]),
        )
        for c in entity["cylinders"]
    ]
    texts = [
        types["foxglove_msgs/msg/TextPrimitive"](
            pose=pose(t["pose"]),
            billboard=t["billboard"],
            font_size=t["font_size"],
            scale_invariant=t["scale_invariant"],
            color=colour(t["color"]),
            text=t["text"],
        )
        for t in entity["texts"]
    ]
    time, lifetime = entity["timestamp"], entity["lifetime"]
    msg = types["foxglove_msgs/msg/SceneEntity"](
        timestamp=types["builtin_interfaces/msg/Time"](sec=time["sec"], nanosec=time["nsec"]),
        frame_id=entity["frame_id"],
        id=entity["id"],
        lifetime=types["builtin_interfaces/msg/Duration"](
            sec=lifetime["sec"], nanosec=lifetime["nsec"]
        ),
        frame_locked=entity["frame_locked"],
        metadata=[
            types["foxglove_msgs/msg/KeyValuePair"](key=m["key"], value=m["value"])
            for m in entity["metadata"]
        ],
        arrows=[],
        cubes=[shape("Cube", c) for c in entity["cubes"]],
        spheres=[shape("Sphere", s) for s in entity["spheres"]],
        cylinders=cylinders,
        lines=[],
        triangles=[],
        texts=texts,
        models=[],
    )
    update = types[SCENE_TYPE](deletions=[], entities=[msg])
    return bytes(store.serialize_cdr(update, SCENE_TYPE))


def add_scene_channel(
    bag: Path | str, updates: Iterable[tuple[int, bytes]], *, episode_id: str
) -> Path:
    """Put ``(time_ns, SceneUpdate CDR)`` pairs into the rosbag2 directory ``bag`` as the
    ``/engram/scenes`` channel (replacing one written before) and return the MCAP file.

    A closed recording keeps its topics, messages and metadata (copied in file order, so replay
    reads it as before) and gains the channel, each update before the first message logged
    after it; ``metadata.yaml`` and the file's ``rosbag2`` metadata record list it. Without a
    recording, a new bag holds the ``/engram/recording`` record and the scenes. The MCAP file
    is replaced atomically (a reader sees the old file or the new one); ``metadata.yaml``
    follows it.

    Raises:
        CorruptRecordingError: the recording cannot be read (cut short, not MCAP, damaged, or
            holding what the recorder never writes); it is left as it was.
    """
    bag = Path(bag)
    ordered = sorted(updates, key=lambda u: u[0])
    if not ordered:
        raise ValueError("updates: at least one scene")
    if not (bag / "metadata.yaml").exists():
        if bag.exists():
            raise CorruptRecordingError(f"{str(bag)!r} has no metadata.yaml (not closed?)")
        return _new_bag(bag, ordered, episode_id)
    return _extend_bag(bag, ordered)


def _new_bag(bag: Path, updates: list[tuple[int, bytes]], episode_id: str) -> Path:
    store = scene_typestore()
    staging = bag.parent / f".scenes-{bag.name}"
    shutil.rmtree(staging, ignore_errors=True)
    writer = BagWriter(
        staging / bag.name,
        typestore=store,
        custom_data={"engram.episode": episode_id, "engram.format": str(FORMAT_VERSION)},
    )
    record = json.dumps({"episode": episode_id, "format": FORMAT_VERSION})
    recording = writer.add_connection(RECORDING_TOPIC, "std_msgs/msg/String")
    scenes = writer.add_connection(SCENE_TOPIC, SCENE_TYPE)
    text = store.types["std_msgs/msg/String"](data=record)
    writer.write(recording, updates[0][0], store.serialize_cdr(text, "std_msgs/msg/String"))
    for time_ns, data in updates:
        writer.write(scenes, time_ns, data)
    writer.close()
    (staging / bag.name).rename(bag)
    staging.rmdir()
    return mcap_file(bag)


def _extend_bag(bag: Path, updates: list[tuple[int, bytes]]) -> Path:
    info = YAML(typ="safe").load((bag / "metadata.yaml").read_text())["rosbag2_bagfile_information"]
    if str(info.get("compression_mode") or "").lower() not in ("", "none", "storage"):
        raise CorruptRecordingError(
            f"{str(bag)!r}: compression mode {info['compression_mode']!r} is not supported"
        )
    files = info.get("relative_file_paths") or []
    if len(files) != 1 or not str(files[0]).endswith(".mcap"):
        raise CorruptRecordingError(f"{str(bag)!r}: not a single-file MCAP bag ({files})")
    file = bag / str(files[0])
    hashes = {
        t["topic_metadata"]["name"]: t["topic_metadata"].get("type_description_hash")
        for t in info.get("topics_with_message_count") or []
    }
    staging = bag.parent / f".scenes-{bag.name}"
    shutil.rmtree(staging, ignore_errors=True)
    try:
        writer = BagWriter(
            staging / bag.name,
            typestore=scene_typestore(),
            compression=_chunk_compression(file),  # rosbags' metadata leaves it out
            custom_data=info.get("custom_data") or {},
        )
        try:
            _copy_with_scenes(file, writer, updates, hashes)
        except (ValueError, KeyError, UnicodeDecodeError) as error:
            raise CorruptRecordingError(f"{str(file)!r} cannot be read: {error}") from error
        written = writer.close()
        os.replace(written, mcap_file(bag))  # a reader sees the old file or the new one
        os.replace(written.with_name("metadata.yaml"), bag / "metadata.yaml")
        if file != mcap_file(bag):
            file.unlink()
    finally:
        shutil.rmtree(staging, ignore_errors=True)
    return mcap_file(bag)


def _chunk_compression(file: Path) -> str | None:
    """The compression of the file's chunks (from its summary; none when it has no summary)."""
    summary = McapFile.open(file).summary
    found = {c.compression for c in summary.chunk_indexes} if summary is not None else set()
    return "lz4" if found == {"lz4"} else ("zstd" if "zstd" in found else None)


def _copy_with_scenes(
    source: Path,
    writer: BagWriter,
    updates: list[tuple[int, bytes]],
    hashes: Mapping[str, str | None],
) -> None:
    """Copy ``source``'s topics and messages through ``writer`` with the scene updates among
    the messages, each before the first message logged after it, so log times never go
    backwards in file order (the recorder's own messages are in log-time order). A scene
    channel written before is left out: the updates replace it."""
    recording = McapFile.open(source)
    if not recording.complete:
        raise CorruptRecordingError(f"{str(source)!r} is cut short (no footer)")
    schemas: dict[int, Schema] = {}
    channels: dict[int, int] = {}
    dropped: set[int] = set()
    pending = list(reversed(updates))  # the earliest last
    scenes: int | None = None

    def scenes_until(time_ns: int | None) -> None:
        nonlocal scenes
        while pending and (time_ns is None or pending[-1][0] <= time_ns):
            if scenes is None:
                scenes = writer.add_connection(SCENE_TOPIC, SCENE_TYPE)
            writer.write(scenes, *pending.pop())

    for record in recording.records():
        if isinstance(record, Schema):
            schemas.setdefault(record.id, record)
        elif isinstance(record, Channel):
            if record.id in channels or record.id in dropped:
                continue
            if record.topic == SCENE_TOPIC:
                dropped.add(record.id)
                continue
            schema = schemas[record.schema_id]
            type_hash = hashes.get(record.topic)
            if not type_hash:
                raise CorruptRecordingError(
                    f"{str(source)!r}: topic {record.topic!r} is not in metadata.yaml"
                )
            channels[record.id] = writer.add_connection(
                record.topic,
                schema.name,
                definition=(schema.encoding, schema.data.decode()),
                type_hash=type_hash,
            )
        elif isinstance(record, Message):
            if record.channel_id not in dropped:
                scenes_until(record.log_time)
                writer.write(channels[record.channel_id], record.log_time, record.data)
        elif isinstance(record, Metadata):
            if record.name != "rosbag2":  # the writer writes the bag's own
                writer.add_metadata(record.name, record.metadata)
        elif isinstance(record, Attachment):
            raise CorruptRecordingError(
                f"{str(source)!r}: holds attachments, which the recorder never writes"
            )
    scenes_until(None)
