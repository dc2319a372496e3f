"""Checks of PLY and PCD files before open3d reads them: header, sizes and every value.

open3d's readers are lenient: a truncated binary PLY comes back with zeros in place of the
missing points and an ASCII line with junk gives garbage coordinates, with no error. These checks
read the header, work out how many points and bytes the body must hold, and refuse a file that
does not hold them, naming the file and what is wrong (:class:`~shapes.errors.SourceError`).

>>> import tempfile, pathlib
>>> path = pathlib.Path(tempfile.mkdtemp()) / "short.ply"
>>> _ = path.write_text("ply\\nformat ascii 1.0\\nelement vertex 2\\nproperty float x\\n"
...                     "property float y\\nproperty float z\\nend_header\\n0 0 1\\n")
>>> try:
...     check_cloud_file(path)
... except SourceError as error:
...     print(str(error).split(": ", 1)[1])
truncated: the header declares 2 vertices, the body has 1 line
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from shapes.errors import SourceError

__all__ = ["CloudLayout", "check_cloud_file"]

_PLY_SIZES = {
    "char": 1,
    "uchar": 1,
    "int8": 1,
    "uint8": 1,
    "short": 2,
    "ushort": 2,
    "int16": 2,
    "uint16": 2,
    "int": 4,
    "uint": 4,
    "int32": 4,
    "uint32": 4,
    "float": 4,
    "float32": 4,
    "double": 8,
    "float64": 8,
}
_MAX_HEADER = 64 * 1024


@dataclass(frozen=True)
class CloudLayout:
    """What the header of a cloud file declares: the point count and, for an organised PCD,
    its (height, width)."""

    points: int
    image_shape: tuple[int, int] | None = None


def _fail(path: Path, problem: str) -> SourceError:
    return SourceError(f"cloud file {str(path)!r}: {problem}")


def _split_header(path: Path, data: bytes, end: bytes) -> tuple[list[str], int]:
    """The header lines (decoded) and the offset of the body."""
    match = re.search(rb"^" + end + rb"[^\n]*\n", data[:_MAX_HEADER], flags=re.MULTILINE)
    if match is None:
        raise _fail(path, f"no '{end.decode()}' line in the first {_MAX_HEADER} bytes")
    try:
        text = data[: match.start()].decode("ascii")
    except UnicodeDecodeError as exc:
        raise _fail(path, f"the header is not ASCII text (byte {exc.start})") from exc
    lines = [*text.splitlines(), data[match.start() : match.end()].decode("ascii", "replace")]
    return [ln.strip() for ln in lines], match.end()


def _check_ascii_rows(
    path: Path, body: bytes, rows: int, columns: int, what: tuple[str, str]
) -> None:
    """Check the first ``rows`` lines: ``columns`` numbers each (``what``: singular, plural)."""
    lines = body.decode("ascii", "replace").splitlines()
    lines = [ln for ln in lines if ln.strip()]
    if len(lines) < rows:
        plural = "line" if len(lines) == 1 else "lines"
        raise _fail(
            path,
            f"truncated: the header declares {rows} {what[1]}, the body has {len(lines)} {plural}",
        )
    for number, line in enumerate(lines[:rows]):
        tokens = line.split()
        if len(tokens) != columns:
            raise _fail(
                path,
                f"{what[0]} {number}: expected {columns} values, got {len(tokens)} ({line[:60]!r})",
            )
    try:
        np.array(" ".join(lines[:rows]).split(), dtype=np.float64)
    except ValueError:
        for number, line in enumerate(lines[:rows]):
            for token in line.split():
                try:
                    float(token)
                except ValueError:
                    raise _fail(
                        path, f"{what[0]} {number}: expected a number, got {token[:30]!r}"
                    ) from None


def _check_ply(path: Path, data: bytes) -> CloudLayout:
    header, body_at = _split_header(path, data, b"end_header")
    if header[0] != "ply":
        raise _fail(path, f"expected 'ply' on the first line, got {header[0][:30]!r}")
    fmt = next((h.split() for h in header if h.startswith("format")), None)
    if fmt is None or len(fmt) < 2:
        raise _fail(path, "no 'format' line in the header")
    encoding = fmt[1]
    if encoding not in ("ascii", "binary_little_endian", "binary_big_endian"):
        raise _fail(
            path,
            f"format: expected ascii, binary_little_endian or binary_big_endian, got {encoding!r}",
        )
    elements: list[tuple[str, int, list[str], int | None]] = []
    for line in header:
        words = line.split()
        if not words:
            continue
        if words[0] == "element":
            if len(words) != 3 or not words[2].isdigit():
                raise _fail(path, f"expected 'element NAME COUNT', got {line[:60]!r}")
            elements.append((words[1], int(words[2]), [], 0))
        elif words[0] == "property":
            if not elements:
                raise _fail(path, f"a property before any element: {line[:60]!r}")
            name, count, props, size = elements[-1]
            if words[1] == "list":
                elements[-1] = (name, count, [*props, words[-1]], None)
                continue
            if len(words) != 3 or words[1] not in _PLY_SIZES:
                raise _fail(path, f"expected 'property TYPE NAME', got {line[:60]!r}")
            new_size = None if size is None else size + _PLY_SIZES[words[1]]
            elements[-1] = (name, count, [*props, words[2]], new_size)
    vertex = next((e for e in elements if e[0] == "vertex"), None)
    if vertex is None:
        raise _fail(path, "no 'element vertex' in the header")
    missing = [a for a in "xyz" if a not in vertex[2]]
    if missing:
        raise _fail(path, f"the vertices have no {', '.join(missing)} property: {vertex[2]}")
    body = data[body_at:]
    if encoding == "ascii":
        if elements[0][0] == "vertex" and vertex[3] is not None:
            _check_ascii_rows(path, body, vertex[1], len(vertex[2]), ("vertex", "vertices"))
        return CloudLayout(vertex[1])
    need = 0
    for name, count, _props, size in elements:
        if size is None:  # a list property: sizes vary, check what comes before it only
            break
        need += count * size
        if name == "vertex":
            break
    if len(body) < need:
        raise _fail(
            path,
            f"truncated: the header declares {vertex[1]} vertices ({need} bytes of data), "
            f"the file has {len(body)} bytes after the header",
        )
    return CloudLayout(vertex[1])


_PCD_TYPES = {"F": (4, 8), "I": (1, 2, 4, 8), "U": (1, 2, 4, 8)}


def _check_pcd(path: Path, data: bytes) -> CloudLayout:
    header, body_at = _split_header(path, data, b"DATA")
    fields: dict[str, list[str]] = {}
    for line in header:
        if line and not line.startswith("#"):
            words = line.split()
            fields[words[0].upper()] = words[1:]
    for key in ("FIELDS", "SIZE", "TYPE", "DATA"):
        if key not in fields:
            raise _fail(path, f"no {key} line in the header")
    names = fields["FIELDS"]
    missing = [a for a in "xyz" if a not in names]
    if missing:
        raise _fail(path, f"FIELDS: no {', '.join(missing)} among {names}")
    counts_raw = fields.get("COUNT", ["1"] * len(names))
    for key, values in (("SIZE", fields["SIZE"]), ("TYPE", fields["TYPE"]), ("COUNT", counts_raw)):
        if len(values) != len(names):
            raise _fail(path, f"{key}: expected {len(names)} values (one per field), got {values}")
    try:
        sizes = [int(s) for s in fields["SIZE"]]
        counts = [int(c) for c in counts_raw]
        width = int(fields.get("WIDTH", ["0"])[0])
        height = int(fields.get("HEIGHT", ["1"])[0])
        points = int(fields.get("POINTS", [str(width * height)])[0])
    except (ValueError, IndexError) as exc:
        problem = f"expected whole numbers in SIZE, COUNT, WIDTH, HEIGHT, POINTS: {exc}"
        raise _fail(path, problem) from None
    for name, t, s in zip(names, fields["TYPE"], sizes, strict=True):
        if t not in _PCD_TYPES or s not in _PCD_TYPES[t]:
            raise _fail(path, f"field {name}: type {t} of size {s} is not a PCD type")
    if width * height != points:
        raise _fail(
            path, f"POINTS is {points} but WIDTH x HEIGHT is {width} x {height} = {width * height}"
        )
    encoding = fields["DATA"][0].lower() if fields["DATA"] else ""
    row = sum(s * c for s, c in zip(sizes, counts, strict=True))
    body = data[body_at:]
    if encoding == "ascii":
        _check_ascii_rows(path, body, points, sum(counts), ("point", "points"))
    elif encoding == "binary":
        if len(body) < points * row:
            raise _fail(
                path,
                f"truncated: the header declares {points} points ({points * row} bytes of data), "
                f"the file has {len(body)} bytes after the header",
            )
    elif encoding == "binary_compressed":
        if len(body) < 8:
            raise _fail(path, "truncated: no compressed block after the header")
        packed, unpacked = (int(v) for v in np.frombuffer(body[:8], dtype="<u4"))
        if unpacked != points * row:
            raise _fail(
                path,
                f"the compressed block unpacks to {unpacked} bytes, {points} points need "
                f"{points * row}",
            )
        if len(body) - 8 < packed:
            raise _fail(
                path,
                f"truncated: the compressed block has {len(body) - 8} of its {packed} bytes",
            )
    else:
        raise _fail(path, f"DATA: expected ascii, binary or binary_compressed, got {encoding!r}")
    organised = (height, width) if height > 1 else None
    return CloudLayout(points, organised)


def check_cloud_file(path: Path) -> CloudLayout | None:
    """Check a PLY or PCD file against its header; None for the other suffixes (XYZ...).

    Raises SourceError naming the file and the problem: a header without a vertex element or
    x/y/z, a binary body shorter than the header declares, an ASCII row with the wrong number
    of values or a value that is not a number.
    """
    suffix = path.suffix.lower()
    if suffix not in (".ply", ".pcd"):
        return None
    data = path.read_bytes()
    if not data:
        raise _fail(path, "no point could be read (empty file)")
    return _check_ply(path, data) if suffix == ".ply" else _check_pcd(path, data)
