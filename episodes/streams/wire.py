"""Samples on the wire: JSON batches, a binary batch format, and replayed samples as JSON.

A sample value in JSON is a string, a number, a nested list of numbers, a mapping of joint
parts (``position``, ``velocity``, ``effort``), or an exact binary array
``{"dtype": "uint8", "shape": [480, 640, 3], "b64": "..."}``.

The binary batch (``application/x-engram-batch``) is for images and large arrays: a 4-byte
little-endian length N, N bytes of a UTF-8 JSON manifest, then the payload. In the manifest an
array may be ``{"dtype": ..., "shape": [...], "offset": o, "length": n}``, bytes o..o+n of the
payload. Both carry ``{"ticks": [{"samples": {...}, "time_ns": t, "stamps_ns": {...}}]}``.

>>> import numpy as np
>>> body = encode_batch([{"samples": {"cam": np.zeros((2, 2), np.uint8)}, "time_ns": 5}])
>>> (tick,) = decode_batch(body)
>>> tick.time_ns, tick.samples["cam"].shape, tick.samples["cam"].dtype.name
(5, (2, 2), 'uint8')
"""

from __future__ import annotations

import base64
import binascii
import json
import struct
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from episodes.streams.errors import InvalidSampleError
from episodes.streams.replay import Frame, Sample

__all__ = [
    "BATCH_MEDIA_TYPE",
    "TickRequest",
    "decode_batch",
    "decode_json_batch",
    "decode_value",
    "encode_batch",
    "encode_frame",
    "encode_value",
]

BATCH_MEDIA_TYPE = "application/x-engram-batch"
DTYPES = {"uint8", "uint16", "int16", "int32", "float32", "float64"}
MAX_TICKS = 10_000


@dataclass
class TickRequest:
    """One tick as sent by a client: samples, optional tick time and sensor stamps."""

    samples: dict[str, Any]
    time_ns: int | None = None
    stamps_ns: dict[str, int] = field(default_factory=dict)


def _binary(where: str, ref: Mapping[str, Any], raw: bytes) -> np.ndarray[Any, Any]:
    dtype, shape = ref.get("dtype"), ref.get("shape")
    if dtype not in DTYPES:
        raise InvalidSampleError(f"{where}.dtype", dtype, f"one of {sorted(DTYPES)}")
    if (
        not isinstance(shape, list)
        or not shape
        or not all(isinstance(n, int) and not isinstance(n, bool) and n >= 0 for n in shape)
    ):
        raise InvalidSampleError(f"{where}.shape", shape, "a list of non-negative integers")
    need = int(np.prod(shape)) * np.dtype(dtype).itemsize
    if len(raw) != need:
        raise InvalidSampleError(f"{where}", f"{len(raw)} bytes", f"{need} bytes for {shape}")
    return np.frombuffer(raw, dtype=np.dtype(dtype).newbyteorder("<")).reshape(shape)


def decode_value(where: str, value: Any, payload: bytes | None = None) -> Any:
    """A sample value from its JSON form (``payload``: the binary batch's payload)."""
    if isinstance(value, Mapping):
        if "b64" in value:
            data = value["b64"]
            try:
                raw = base64.b64decode(data, validate=True) if isinstance(data, str) else None
            except binascii.Error:
                raw = None
            if raw is None:
                raise InvalidSampleError(f"{where}.b64", str(data)[:40], "base64 text")
            return _binary(where, value, raw)
        if "offset" in value:
            if payload is None:
                raise InvalidSampleError(where, "offset", f"an offset only in {BATCH_MEDIA_TYPE}")
            offset, length = value.get("offset"), value.get("length")
            if (
                not isinstance(offset, int)
                or not isinstance(length, int)
                or offset < 0
                or length < 0
                or offset + length > len(payload)
            ):
                raise InvalidSampleError(
                    f"{where}.offset", [offset, length], f"a range inside {len(payload)} bytes"
                )
            return _binary(where, value, payload[offset : offset + length])
        return {str(k): decode_value(f"{where}.{k}", v, payload) for k, v in value.items()}
    return value


def _ticks(manifest: Any, payload: bytes | None) -> list[TickRequest]:
    if not isinstance(manifest, Mapping) or not isinstance(manifest.get("ticks"), list):
        raise InvalidSampleError("ticks", type(manifest).__name__, '{"ticks": [...]}')
    if set(manifest) - {"ticks"}:
        raise InvalidSampleError("body", sorted(set(manifest) - {"ticks"}), 'only "ticks"')
    ticks = manifest["ticks"]
    if not 0 < len(ticks) <= MAX_TICKS:
        raise InvalidSampleError("ticks", f"{len(ticks)} ticks", f"1 to {MAX_TICKS} ticks")
    out = []
    for i, tick in enumerate(ticks):
        where = f"ticks[{i}]"
        if not isinstance(tick, Mapping) or not isinstance(tick.get("samples"), Mapping):
            raise InvalidSampleError(f"{where}.samples", tick, "an object provider -> value")
        if not tick["samples"]:
            raise InvalidSampleError(f"{where}.samples", {}, "at least one sample")
        unknown = set(tick) - {"samples", "time_ns", "stamps_ns"}
        if unknown:
            raise InvalidSampleError(where, sorted(unknown), "only samples, time_ns, stamps_ns")
        stamps = tick.get("stamps_ns") or {}
        if not isinstance(stamps, Mapping):
            raise InvalidSampleError(f"{where}.stamps_ns", stamps, "an object provider -> ns")
        out.append(
            TickRequest(
                samples={
                    str(name): decode_value(f"{where}.samples[{name}]", value, payload)
                    for name, value in tick["samples"].items()
                },
                time_ns=tick.get("time_ns"),
                stamps_ns=dict(stamps),
            )
        )
    return out


def decode_json_batch(body: bytes) -> list[TickRequest]:
    """Ticks from a JSON batch.

    Raises:
        InvalidSampleError: not JSON, or not the expected structure.
    """
    try:
        manifest = json.loads(body)
    except (UnicodeDecodeError, json.JSONDecodeError) as exc:
        raise InvalidSampleError("body", f"{len(body)} bytes", f"JSON ({exc})") from None
    return _ticks(manifest, None)


def decode_batch(body: bytes) -> list[TickRequest]:
    """Ticks from a binary batch (see the module docstring).

    Raises:
        InvalidSampleError: truncated, bad manifest, or a reference outside the payload.
    """
    if len(body) < 4:
        raise InvalidSampleError("body", f"{len(body)} bytes", "4-byte manifest length first")
    (size,) = struct.unpack_from("<I", body, 0)
    if 4 + size > len(body):
        raise InvalidSampleError("body", f"manifest length {size}", f"<= {len(body) - 4}")
    try:
        manifest = json.loads(body[4 : 4 + size])
    except (UnicodeDecodeError, json.JSONDecodeError) as exc:
        raise InvalidSampleError("manifest", f"{size} bytes", f"JSON ({exc})") from None
    return _ticks(manifest, body[4 + size :])


def encode_batch(ticks: Sequence[Mapping[str, Any]]) -> bytes:
    """A binary batch: every numpy array goes to the payload, the rest into the manifest."""
    payload = bytearray()

    def ref(value: Any) -> Any:
        if isinstance(value, np.ndarray):
            arr = np.ascontiguousarray(value, dtype=value.dtype.newbyteorder("<"))
            out = {
                "dtype": arr.dtype.name,
                "shape": list(arr.shape),
                "offset": len(payload),
                "length": arr.nbytes,
            }
            payload.extend(arr.tobytes())
            return out
        if isinstance(value, Mapping):
            return {k: ref(v) for k, v in value.items()}
        return value

    manifest = json.dumps({"ticks": [ref(dict(t)) for t in ticks]}).encode()
    return struct.pack("<I", len(manifest)) + manifest + bytes(payload)


def encode_value(value: Any) -> Any:
    """A replayed value as JSON: arrays exact, as dtype, shape and base64."""
    if isinstance(value, np.ndarray):
        arr = np.ascontiguousarray(value, dtype=value.dtype.newbyteorder("<"))
        return {
            "dtype": arr.dtype.name,
            "shape": list(arr.shape),
            "b64": base64.b64encode(arr.tobytes()).decode(),
        }
    if isinstance(value, Mapping):
        return {k: encode_value(v) for k, v in value.items()}
    return value


def _sample(sample: Sample) -> dict[str, Any]:
    return {
        "episode": sample.episode,
        "provider": sample.provider,
        "channel": sample.channel,
        "kind": sample.kind.value,
        "time_ns": sample.time_ns,
        "frame": sample.frame,
        "stamp_ns": sample.stamp_ns,
        "from_baseline": sample.from_baseline,
        "value": encode_value(sample.value),
    }


def encode_frame(frame: Frame) -> bytes:
    """One NDJSON line for a replayed frame."""
    line = {
        "frame": frame.number,
        "time_ns": frame.time_ns,
        "samples": [_sample(s) for s in frame.samples.values()],
    }
    return json.dumps(line, separators=(",", ":")).encode() + b"\n"
