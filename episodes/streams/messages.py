"""Typed channels: what a provider records, how a sample is checked, encoded and decoded.

Every provider has a :class:`Kind`. Samples are checked against it in the producer's thread
(so bad input fails at once and changes nothing) and turned into ROS 2 messages (CDR, the
rosbag2 encoding) in the writer's thread. Standard ROS types are used where they exist:

=============  ===================================  ============================================
kind           ROS 2 message type                   sample value (Python side)
=============  ===================================  ============================================
joint_state    ``sensor_msgs/msg/JointState``       1-D positions, or a mapping with
                                                    ``position`` / ``velocity`` / ``effort``
float_array    ``std_msgs/msg/Float32MultiArray``   numpy array of float32 or float64, any shape
               or ``Float64MultiArray``
image          ``sensor_msgs/msg/Image``            numpy array (height, width[, channels])
audio          ``engram_msgs/msg/Audio``            numpy int16 or float32 (frames, channels)
string         ``std_msgs/msg/String``              ``str``
=============  ===================================  ============================================

Engram's own types (``engram_msgs/msg/*``) carry what no standard type does: the tick record
(frame number, each sensor's own timestamp), the provider's settings, audio, and samples of a
baseline-filtered provider (only the elements that differ from the baseline). Their
definitions are stored inside every bag, so ``rosbags`` and Foxglove read them too.

>>> spec = ProviderSpec.create("icub/skin/torso", "float_array", dtype="float64", shape=[3])
>>> spec.topic, spec.msgtype
('/icub/skin/torso', 'std_msgs/msg/Float64MultiArray')
>>> decode(spec, encode(spec, 7, check(spec, [1.0, 2.0, 3.0]))).tolist()
[1.0, 2.0, 3.0]
"""

from __future__ import annotations

import enum
import json
import math
import re
import struct
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from functools import lru_cache
from typing import Any

import numpy as np
from numpy.typing import NDArray
from rosbags.serde.errors import SerdeError
from rosbags.typesys import Stores, get_types_from_msg, get_typestore
from rosbags.typesys.store import Typestore

from episodes.streams.errors import InvalidSampleError

__all__ = [
    "AUDIO_TYPE",
    "DECODE_ERRORS",
    "IMAGE_ENCODINGS",
    "PROVIDER_TYPE",
    "SPARSE_TYPE",
    "TICK_TYPE",
    "Kind",
    "ProviderSpec",
    "check",
    "decode",
    "encode",
    "typestore",
]

DECODE_ERRORS = (
    SerdeError,
    ValueError,  # also JSON's, UnicodeDecodeError, InvalidSampleError (a provider's settings)
    struct.error,
    KeyError,
    IndexError,
    TypeError,
    OverflowError,
)
"""What decoding a damaged message's bytes can raise."""

TICK_TYPE = "engram_msgs/msg/Tick"
PROVIDER_TYPE = "engram_msgs/msg/Provider"
SPARSE_TYPE = "engram_msgs/msg/SparseArray"
AUDIO_TYPE = "engram_msgs/msg/Audio"

_DEFINITIONS = {
    # One per recording tick, written after that tick's samples, at the tick time. `stored`
    # is 1 when the sample is a message on its channel, 0 when it equalled the provider's
    # baseline and was left out (restored on read).
    TICK_TYPE: "uint64 frame\nint64 tick_time_ns\nstring[] providers\nint64[] stamps_ns\n"
    "uint8[] stored\n",
    # One per provider, written when it is registered; `baseline` is the raw little-endian
    # bytes of the baseline array (dtype and shape in config_json).
    PROVIDER_TYPE: "string name\nstring kind\nstring topic\nstring config_json\nuint8[] baseline\n",
    # A sample of a baseline-filtered float array: the flat indices and raw bytes of the
    # elements whose bits differ from the baseline.
    SPARSE_TYPE: "uint32[] shape\nstring dtype\nuint32[] indices\nuint8[] values\n",
    AUDIO_TYPE: "std_msgs/Header header\nuint32 sample_rate\nuint16 channels\n"
    "string format\nuint8[] data\n",
}


@lru_cache(maxsize=1)
def typestore() -> Typestore:
    """The ROS 2 (Jazzy) type store with Engram's message types registered."""
    store = get_typestore(Stores.ROS2_JAZZY)
    for name, text in _DEFINITIONS.items():
        store.register(get_types_from_msg(text, name))
    return store


class Kind(enum.StrEnum):
    """What a provider records."""

    JOINT_STATE = "joint_state"
    FLOAT_ARRAY = "float_array"
    IMAGE = "image"
    AUDIO = "audio"
    STRING = "string"


# image encoding -> (dtype, channels)
IMAGE_ENCODINGS: dict[str, tuple[str, int]] = {
    "rgb8": ("uint8", 3),
    "bgr8": ("uint8", 3),
    "rgba8": ("uint8", 4),
    "mono8": ("uint8", 1),
    "mono16": ("uint16", 1),
    "16UC1": ("uint16", 1),
    "32FC1": ("float32", 1),
}
_AUDIO_FORMATS = {"s16le": "int16", "f32le": "float32"}
_NAME = re.compile(r"[A-Za-z][A-Za-z0-9_]*(/[A-Za-z][A-Za-z0-9_]*)*")
RESERVED_PREFIX = "engram/"


def _positive_int(name: str, value: Any) -> int:
    if isinstance(value, bool) or not isinstance(value, int) or value <= 0:
        raise InvalidSampleError(name, value, "a positive integer")
    return value


@dataclass(frozen=True)
class ProviderSpec:
    """A provider's name, kind and settings; build it with :meth:`create`, which checks them."""

    name: str
    kind: Kind
    dtype: str = ""
    shape: tuple[int, ...] | None = None
    encoding: str = ""
    names: tuple[str, ...] = ()
    sample_rate: int = 0
    channels: int = 0
    rate_limit_hz: float | None = None
    baseline: NDArray[Any] | None = field(default=None, compare=False)
    threshold: float = 0.0
    """The skin filter's bound θ (Petit et al. 2016): an element within θ of its baseline is
    stored as the baseline. 0 is the lossless mode (only bit-equal elements are left out)."""

    @property
    def topic(self) -> str:
        """The bag topic of the provider: its name with a leading slash."""
        return "/" + self.name

    @property
    def msgtype(self) -> str:
        """The ROS 2 message type of the provider's channel in the recorder's own file."""
        if self.kind is Kind.FLOAT_ARRAY:
            if self.baseline is not None:
                return SPARSE_TYPE
            return (
                "std_msgs/msg/Float32MultiArray"
                if self.dtype == "float32"
                else ("std_msgs/msg/Float64MultiArray")
            )
        return {
            Kind.JOINT_STATE: "sensor_msgs/msg/JointState",
            Kind.IMAGE: "sensor_msgs/msg/Image",
            Kind.AUDIO: AUDIO_TYPE,
            Kind.STRING: "std_msgs/msg/String",
        }[self.kind]

    @property
    def dense_msgtype(self) -> str:
        """The standard message type used on export (a filtered array becomes dense)."""
        if self.kind is Kind.FLOAT_ARRAY:
            return (
                "std_msgs/msg/Float32MultiArray"
                if self.dtype == "float32"
                else ("std_msgs/msg/Float64MultiArray")
            )
        return self.msgtype

    def config(self) -> dict[str, Any]:
        """The settings as JSON-ready values (the baseline is stored apart, as raw bytes)."""
        out: dict[str, Any] = {"name": self.name, "kind": self.kind.value}
        if self.dtype:
            out["dtype"] = self.dtype
        if self.shape is not None:
            out["shape"] = list(self.shape)
        if self.encoding:
            out["encoding"] = self.encoding
        if self.names:
            out["names"] = list(self.names)
        if self.sample_rate:
            out["sample_rate"] = self.sample_rate
        if self.channels:
            out["channels"] = self.channels
        if self.rate_limit_hz is not None:
            out["rate_limit_hz"] = self.rate_limit_hz
        if self.baseline is not None:
            out["baseline"] = {
                "dtype": str(self.baseline.dtype),
                "shape": list(self.baseline.shape),
            }
        if self.threshold:
            out["threshold"] = self.threshold
        return out

    @classmethod
    def create(
        cls,
        name: str,
        kind: str | Kind,
        *,
        dtype: str | None = None,
        shape: Sequence[int] | None = None,
        encoding: str | None = None,
        names: Sequence[str] | None = None,
        sample_rate: int | None = None,
        channels: int | None = None,
        rate_limit_hz: float | None = None,
        baseline: Any = None,
        threshold: float | None = None,
    ) -> ProviderSpec:
        """Check and build a provider's settings.

        Raises:
            InvalidSampleError: a setting is missing, unknown or out of range; the message
                names the setting, the value given and what is expected.
        """
        if not isinstance(name, str) or not _NAME.fullmatch(name) or len(name) > 200:
            raise InvalidSampleError(
                "name", name, "a ROS-style name: letters, digits, '_', parts split by '/'"
            )
        if name.startswith(RESERVED_PREFIX) or name == "engram":
            raise InvalidSampleError("name", name, "a name outside the reserved 'engram/' prefix")
        try:
            kind = Kind(kind)
        except ValueError:
            raise InvalidSampleError("kind", kind, f"one of {[k.value for k in Kind]}") from None
        if rate_limit_hz is not None and (
            isinstance(rate_limit_hz, bool)
            or not isinstance(rate_limit_hz, int | float)
            or not 0 < rate_limit_hz < 1e6
        ):
            raise InvalidSampleError("rate_limit_hz", rate_limit_hz, "a number of Hz above 0")
        rate = float(rate_limit_hz) if rate_limit_hz is not None else None
        if baseline is not None and kind is not Kind.FLOAT_ARRAY:
            raise InvalidSampleError("baseline", "<given>", "no baseline except for float_array")
        bound = 0.0
        if threshold is not None:
            if (
                isinstance(threshold, bool)
                or not isinstance(threshold, int | float)
                or not math.isfinite(threshold)
                or threshold < 0
            ):
                raise InvalidSampleError("threshold", threshold, "a finite number >= 0")
            if threshold and baseline is None:
                raise InvalidSampleError(
                    "threshold", threshold, "a baseline to compare with (float_array only)"
                )
            bound = float(threshold)
        shape_t = _check_shape(shape) if shape is not None else None
        if kind is Kind.FLOAT_ARRAY:
            dtype = dtype or "float64"
            if dtype not in ("float32", "float64"):
                raise InvalidSampleError("dtype", dtype, "'float32' or 'float64'")
            base = None
            if baseline is not None:
                base = np.asarray(baseline, dtype=dtype)
                if shape_t is not None and base.ndim and base.shape != shape_t:
                    raise InvalidSampleError("baseline", base.shape, f"shape {shape_t}")
                if shape_t is None and base.ndim == 0:
                    raise InvalidSampleError("shape", None, "a shape when the baseline is a scalar")
                if shape_t is None:
                    shape_t = base.shape
                if base.ndim == 0:
                    base = np.full(shape_t, base, dtype=dtype)
                base = np.ascontiguousarray(base)
                base.setflags(write=False)
            return cls(
                name,
                kind,
                dtype=dtype,
                shape=shape_t,
                rate_limit_hz=rate,
                baseline=base,
                threshold=bound,
            )
        if kind is Kind.JOINT_STATE:
            if names is None or isinstance(names, str):
                raise InvalidSampleError("names", names, "the list of joint names")
            joint_names = tuple(names)
            if not joint_names or not all(isinstance(n, str) for n in joint_names):
                raise InvalidSampleError("names", names, "a non-empty list of strings")
            return cls(name, kind, names=joint_names, rate_limit_hz=rate)
        if kind is Kind.IMAGE:
            encoding = encoding or "rgb8"
            if encoding not in IMAGE_ENCODINGS:
                raise InvalidSampleError("encoding", encoding, f"one of {sorted(IMAGE_ENCODINGS)}")
            if shape_t is not None and len(shape_t) != 2:
                raise InvalidSampleError("shape", list(shape_t), "[height, width]")
            return cls(name, kind, encoding=encoding, shape=shape_t, rate_limit_hz=rate)
        if kind is Kind.AUDIO:
            fmt = encoding or "s16le"
            if fmt not in _AUDIO_FORMATS:
                raise InvalidSampleError("encoding", fmt, f"one of {sorted(_AUDIO_FORMATS)}")
            return cls(
                name,
                kind,
                encoding=fmt,
                sample_rate=_positive_int("sample_rate", sample_rate),
                channels=_positive_int("channels", channels if channels is not None else 1),
                rate_limit_hz=rate,
            )
        return cls(name, kind, rate_limit_hz=rate)

    @classmethod
    def from_config(cls, config: Mapping[str, Any], baseline: bytes = b"") -> ProviderSpec:
        """Rebuild a spec from :meth:`config` and the stored baseline bytes."""
        args = {k: v for k, v in config.items() if k not in ("name", "kind", "baseline")}
        base = None
        if "baseline" in config:
            info = config["baseline"]
            base = np.frombuffer(baseline, dtype=info["dtype"]).reshape(info["shape"])
        return cls.create(config["name"], config["kind"], baseline=base, **args)


def _check_shape(shape: Any) -> tuple[int, ...]:
    if isinstance(shape, str | bytes) or not isinstance(shape, Sequence) or not shape:
        raise InvalidSampleError("shape", shape, "a non-empty list of positive integers")
    for n in shape:
        _positive_int("shape", n)
    return tuple(int(n) for n in shape)


def _array(spec: ProviderSpec, value: Any, dtype: str, what: str) -> NDArray[Any]:
    """The value as an array of ``dtype``. Plain Python numbers convert (they have no dtype);
    a numpy array must not narrow (float64 into float32, floats into integers): that would
    change bits silently."""
    field_name = f"samples[{spec.name}]"
    target = np.dtype(dtype)
    typed = isinstance(value, np.ndarray | np.generic)
    try:
        arr = np.asarray(value)
    except (TypeError, ValueError) as exc:
        raise InvalidSampleError(field_name, type(value).__name__, what) from exc
    if arr.dtype == object or arr.dtype.kind not in "biuf":
        raise InvalidSampleError(field_name, f"array of {arr.dtype}", what)
    if arr.dtype != target:
        if typed and not np.can_cast(arr.dtype, target, casting="safe"):
            raise InvalidSampleError(field_name, f"array of {arr.dtype}", what)
        if not typed and arr.dtype.kind == "f" and target.kind in "iu":
            raise InvalidSampleError(field_name, f"array of {arr.dtype}", what)
        if not typed and target.kind in "iu" and arr.size:
            low, high = np.iinfo(target).min, np.iinfo(target).max
            if arr.min() < low or arr.max() > high:
                raise InvalidSampleError(
                    field_name, f"values {arr.min()}..{arr.max()}", f"{what} ({low}..{high})"
                )
        arr = arr.astype(target)
    return arr


def check(spec: ProviderSpec, value: Any) -> Any:
    """Check one sample against its provider and return it in canonical form (a private copy).

    Raises:
        InvalidSampleError: wrong type, dtype or shape (the message says which).
    """
    field_name = f"samples[{spec.name}]"
    if spec.kind is Kind.STRING:
        if not isinstance(value, str):
            raise InvalidSampleError(field_name, type(value).__name__, "a string")
        return value
    if spec.kind is Kind.JOINT_STATE:
        parts = value if isinstance(value, Mapping) else {"position": value}
        unknown = set(parts) - {"position", "velocity", "effort"}
        if unknown:
            raise InvalidSampleError(field_name, sorted(unknown), "position, velocity, effort")
        out: dict[str, NDArray[Any]] = {}
        for key in ("position", "velocity", "effort"):
            part = parts.get(key)
            if part is None or np.size(part) == 0:
                out[key] = np.zeros(0, dtype=np.float64)
                continue
            arr = _array(spec, part, "float64", f"{len(spec.names)} float64 {key}s")
            if arr.shape != (len(spec.names),):
                raise InvalidSampleError(
                    f"{field_name}.{key}", list(arr.shape), f"[{len(spec.names)}] (one per joint)"
                )
            out[key] = np.array(arr, copy=True)
        return out
    if spec.kind is Kind.FLOAT_ARRAY:
        arr = _array(spec, value, spec.dtype, f"a {spec.dtype} array")
        if arr.ndim == 0:
            arr = arr.reshape(1)
        if spec.shape is not None and arr.shape != spec.shape:
            raise InvalidSampleError(field_name, list(arr.shape), f"shape {list(spec.shape)}")
        return np.array(arr, copy=True, order="C")
    if spec.kind is Kind.IMAGE:
        dtype, nchan = IMAGE_ENCODINGS[spec.encoding]
        arr = _array(spec, value, dtype, f"a {dtype} image for encoding {spec.encoding}")
        want = 2 if nchan == 1 else 3
        if arr.ndim == 3 and nchan == 1 and arr.shape[2] == 1:
            arr = arr[:, :, 0]
        if arr.ndim != want or (nchan > 1 and arr.shape[2] != nchan):
            expected = "(height, width)" if nchan == 1 else f"(height, width, {nchan})"
            raise InvalidSampleError(field_name, list(arr.shape), f"an array of shape {expected}")
        if spec.shape is not None and arr.shape[:2] != spec.shape:
            raise InvalidSampleError(field_name, list(arr.shape[:2]), f"{list(spec.shape)}")
        return np.array(arr, copy=True, order="C")
    # audio
    arr = _array(spec, value, _AUDIO_FORMATS[spec.encoding], f"{spec.encoding} samples")
    if arr.ndim == 1 and spec.channels == 1:
        arr = arr.reshape(-1, 1)
    if arr.ndim != 2 or arr.shape[1] != spec.channels:
        raise InvalidSampleError(field_name, list(arr.shape), f"(frames, {spec.channels})")
    return np.array(arr, copy=True, order="C")


def _stamp(ns: int) -> Any:
    types = typestore().types
    sec, nanosec = divmod(ns, 1_000_000_000)
    return types["std_msgs/msg/Header"](
        stamp=types["builtin_interfaces/msg/Time"](sec=sec, nanosec=nanosec), frame_id=""
    )


def _layout(shape: Sequence[int]) -> Any:
    types = typestore().types
    dims = []
    stride = int(np.prod(shape))
    for i, size in enumerate(shape):
        dims.append(
            types["std_msgs/msg/MultiArrayDimension"](label=f"dim{i}", size=size, stride=stride)
        )
        stride //= max(size, 1)
    return types["std_msgs/msg/MultiArrayLayout"](dim=dims, data_offset=0)


def sparse_of(spec: ProviderSpec, value: NDArray[Any]) -> tuple[NDArray[np.uint32], bytes] | None:
    """Indices and raw bytes of the elements the filter keeps; None if none.

    Lossless (threshold 0): the elements whose bits differ from the baseline. With a
    threshold θ: the elements farther than θ from the baseline (and NaNs), so an element within
    θ is stored as the baseline; the others are stored exactly.
    """
    assert spec.baseline is not None
    if spec.threshold:
        gap = np.abs(value.reshape(-1).astype(np.float64) - spec.baseline.reshape(-1))
        differ = np.flatnonzero(~(gap <= spec.threshold))
    else:
        width = np.dtype(f"u{value.dtype.itemsize}")
        flat = value.reshape(-1).view(width)
        differ = np.flatnonzero(flat != spec.baseline.reshape(-1).view(width))
    if differ.size == 0:
        return None
    return differ.astype(np.uint32), value.reshape(-1)[differ].tobytes()


def encode(spec: ProviderSpec, stamp_ns: int, value: Any, sparse: Any = None) -> Any:
    """The ROS message for a checked sample (``sparse``: the result of :func:`sparse_of`)."""
    types = typestore().types
    if spec.kind is Kind.STRING:
        return types["std_msgs/msg/String"](data=value)
    if spec.kind is Kind.JOINT_STATE:
        return types["sensor_msgs/msg/JointState"](
            header=_stamp(stamp_ns),
            name=list(spec.names),
            position=value["position"],
            velocity=value["velocity"],
            effort=value["effort"],
        )
    if spec.kind is Kind.FLOAT_ARRAY:
        if sparse is not None:
            indices, raw = sparse
            return types[SPARSE_TYPE](
                shape=np.asarray(value.shape, dtype=np.uint32),
                dtype=str(value.dtype),
                indices=indices,
                values=np.frombuffer(raw, dtype=np.uint8),
            )
        return types[spec.dense_msgtype](layout=_layout(value.shape), data=value.reshape(-1))
    if spec.kind is Kind.IMAGE:
        height, width = value.shape[:2]
        return types["sensor_msgs/msg/Image"](
            header=_stamp(stamp_ns),
            height=height,
            width=width,
            encoding=spec.encoding,
            is_bigendian=0,
            step=width * (value.shape[2] if value.ndim == 3 else 1) * value.dtype.itemsize,
            data=value.reshape(-1).view(np.uint8),
        )
    return types[AUDIO_TYPE](
        header=_stamp(stamp_ns),
        sample_rate=spec.sample_rate,
        channels=spec.channels,
        format=spec.encoding,
        data=value.reshape(-1).view(np.uint8),
    )


def decode(spec: ProviderSpec, msg: Any) -> Any:
    """The sample value of a message, in the form :func:`check` returns (arrays are copies)."""
    if spec.kind is Kind.STRING:
        return str(msg.data)
    if spec.kind is Kind.JOINT_STATE:
        return {
            key: np.array(getattr(msg, key), dtype=np.float64)
            for key in ("position", "velocity", "effort")
        }
    if spec.kind is Kind.FLOAT_ARRAY:
        if msg.__msgtype__ == SPARSE_TYPE:
            assert spec.baseline is not None
            out = np.array(spec.baseline, copy=True).reshape(-1)
            out[np.asarray(msg.indices, dtype=np.intp)] = np.frombuffer(
                np.asarray(msg.values, dtype=np.uint8).tobytes(), dtype=spec.dtype
            )
            return out.reshape(tuple(int(n) for n in msg.shape))
        shape = [int(d.size) for d in msg.layout.dim] or [len(msg.data)]
        return np.array(msg.data, dtype=spec.dtype).reshape(shape)
    if spec.kind is Kind.IMAGE:
        dtype, nchan = IMAGE_ENCODINGS[spec.encoding]
        dims = (msg.height, msg.width) if nchan == 1 else (msg.height, msg.width, nchan)
        raw = np.asarray(msg.data, dtype=np.uint8).tobytes()
        return np.frombuffer(raw, dtype=dtype).reshape(dims).copy()
    raw = np.asarray(msg.data, dtype=np.uint8).tobytes()
    fmt = _AUDIO_FORMATS[str(msg.format)]
    return np.frombuffer(raw, dtype=fmt).reshape(-1, int(msg.channels)).copy()


def nbytes(value: Any) -> int:
    """Approximate size of a checked sample in memory, for the queue's byte budget."""
    if isinstance(value, str):
        return len(value) + 64
    if isinstance(value, dict):
        return sum(int(v.nbytes) for v in value.values()) + 64
    return int(value.nbytes) + 64


def config_json(spec: ProviderSpec) -> str:
    """The provider's settings as compact JSON (stored in the bag)."""
    return json.dumps(spec.config(), separators=(",", ":"), sort_keys=True)
