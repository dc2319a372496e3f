"""Stored scenes as Foxglove's ``foxglove.SceneUpdate`` messages, in an MCAP file of their own.

Each scene becomes one ``SceneEntity`` (id: the scene's name) whose primitives are Foxglove
spheres, cylinders (a cone is a cylinder with ``top_scale`` 0) and cubes (a plane is a thin
square across its normal), at the stored centres, sizes, axes and colours, with a text label per
primitive; frame ``world``, x right, y behind, z up, metres. Messages use the ``json`` encoding
with the ``jsonschema`` of ``foxglove.SceneUpdate`` (the fields written here, as Foxglove's
schema defines them), so Foxglove and Lichtblick draw them in their 3D panel.

The file is separate from the episode's rosbag2 recording on purpose: ``rosbags`` (and so
``ros2 bag`` tooling and Engram's bag import) refuse a ``jsonschema`` schema inside a rosbag2
MCAP. Pure files, no RDF: :mod:`episodes.scene_channel` reads the scenes from the graph.

>>> ball = {"id": "ball", "kind": "Sphere", "centre": (0.1, 0.0, 0.05), "radius": 0.05}
>>> entity = scene_entity("experience-1", [ball], time_ns=1_500_000_000)
>>> entity["spheres"][0]["size"], entity["timestamp"]
({'x': 0.1, 'y': 0.1, 'z': 0.1}, {'sec': 1, 'nsec': 500000000})
"""

import json
import math
import os
from collections.abc import Iterable, Mapping, Sequence
from pathlib import Path
from typing import Any

from mcap.writer import CompressionType, Writer

__all__ = ["SCENE_TOPIC", "SCHEMA_NAME", "scene_entity", "scene_update", "write_scene_mcap"]

SCHEMA_NAME = "foxglove.SceneUpdate"
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

_VECTOR3 = {
    "type": "object",
    "properties": {k: {"type": "number"} for k in ("x", "y", "z")},
}
_QUATERNION = {
    "type": "object",
    "properties": {k: {"type": "number"} for k in ("x", "y", "z", "w")},
}
_POSE = {"type": "object", "properties": {"position": _VECTOR3, "orientation": _QUATERNION}}
_COLOR = {"type": "object", "properties": {k: {"type": "number"} for k in ("r", "g", "b", "a")}}
_TIME = {
    "type": "object",
    "properties": {"sec": {"type": "integer"}, "nsec": {"type": "integer"}},
}
_SHAPE = {"type": "object", "properties": {"pose": _POSE, "size": _VECTOR3, "color": _COLOR}}
_CYLINDER = {
    "type": "object",
    "properties": {
        "pose": _POSE,
        "size": _VECTOR3,
        "bottom_scale": {"type": "number"},
        "top_scale": {"type": "number"},
        "color": _COLOR,
    },
}
_TEXT = {
    "type": "object",
    "properties": {
        "pose": _POSE,
        "billboard": {"type": "boolean"},
        "font_size": {"type": "number"},
        "scale_invariant": {"type": "boolean"},
        "color": _COLOR,
        "text": {"type": "string"},
    },
}
SCHEMA: dict[str, Any] = {
    "title": SCHEMA_NAME,
    "description": "An update to the entities displayed in a 3D scene",
    "$comment": "The fields of Foxglove's foxglove.SceneUpdate schema that Engram writes",
    "type": "object",
    "properties": {
        "deletions": {"type": "array", "items": {"type": "object"}},
        "entities": {
            "type": "array",
            "items": {
                "type": "object",
                "properties": {
                    "timestamp": _TIME,
                    "frame_id": {"type": "string"},
                    "id": {"type": "string"},
                    "lifetime": {
                        "type": "object",
                        "properties": {"sec": {"type": "integer"}, "nsec": {"type": "integer"}},
                    },
                    "frame_locked": {"type": "boolean"},
                    "metadata": {"type": "array", "items": {"type": "object"}},
                    "arrows": {"type": "array", "items": {"type": "object"}},
                    "cubes": {"type": "array", "items": _SHAPE},
                    "spheres": {"type": "array", "items": _SHAPE},
                    "cylinders": {"type": "array", "items": _CYLINDER},
                    "lines": {"type": "array", "items": {"type": "object"}},
                    "triangles": {"type": "array", "items": {"type": "object"}},
                    "texts": {"type": "array", "items": _TEXT},
                    "models": {"type": "array", "items": {"type": "object"}},
                },
            },
        },
    },
}
"""The JSON schema stored with the channel."""


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


def _colour(primitive: Mapping[str, Any]) -> dict[str, float]:
    r, g, b = primitive.get("colour") or _DEFAULT_COLOURS[primitive["kind"]]
    return {"r": float(r), "g": float(g), "b": float(b), "a": 1.0}


def _time(time_ns: int) -> dict[str, int]:
    return {"sec": time_ns // 1_000_000_000, "nsec": time_ns % 1_000_000_000}


def scene_entity(
    scene_id: str, primitives: Iterable[Mapping[str, Any]], *, time_ns: int
) -> dict[str, Any]:
    """One ``SceneEntity`` drawing ``primitives`` (dicts with ``id``, ``kind``, ``centre`` and
    optionally ``axis``, ``radius``, ``height``, ``colour``)."""
    spheres, cylinders, cubes, texts = [], [], [], []
    for p in primitives:
        radius = float(p.get("radius") or 0.05)
        height = float(p.get("height") or 2 * radius)
        pose = {"position": _vector(p["centre"]), "orientation": _rotation_from_z(p.get("axis"))}
        colour = _colour(p)
        kind = p["kind"]
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
        label_at = dict(
            pose, position=_vector((p["centre"][0], p["centre"][1], p["centre"][2] + 0.02))
        )
        texts.append(
            {
                "pose": label_at,
                "billboard": True,
                "font_size": 12.0,
                "scale_invariant": True,
                "color": {"r": 0.1, "g": 0.1, "b": 0.1, "a": 1.0},
                "text": str(p["id"]),
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


def scene_update(entity: Mapping[str, Any]) -> bytes:
    """A ``SceneUpdate`` replacing what was shown by ``entity`` (JSON, UTF-8)."""
    return json.dumps({"deletions": [], "entities": [entity]}, separators=(",", ":")).encode()


def write_scene_mcap(path: Path | str, updates: Iterable[tuple[int, bytes]]) -> Path:
    """Write ``(time_ns, SceneUpdate JSON)`` pairs, oldest first, as the MCAP file ``path``
    (one ``/engram/scenes`` channel), atomically: a reader sees the old file or the new one."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    partial = path.with_name(path.name + ".part")
    with partial.open("wb") as stream:
        writer = Writer(stream, compression=CompressionType.NONE)
        writer.start(profile="", library="engram")
        schema = writer.register_schema(
            SCHEMA_NAME, "jsonschema", json.dumps(SCHEMA, separators=(",", ":")).encode()
        )
        channel = writer.register_channel(SCENE_TOPIC, "json", schema)
        for sequence, (time_ns, data) in enumerate(sorted(updates, key=lambda u: u[0])):
            writer.add_message(channel, time_ns, data, time_ns, sequence)
        writer.finish()  # type: ignore[no-untyped-call]
        stream.flush()
        os.fsync(stream.fileno())
    partial.replace(path)
    return path
