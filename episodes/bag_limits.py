"""Bounded decompression for ``rosbags``: a bag's compressed chunks and messages may not expand
past a limit, checked while decompressing.

``rosbags`` decompresses a ROS 1 chunk (bz2, lz4), a ROS 2 message or file (zstd) and an MCAP
chunk (lz4, zstd) whole, with no bound: a few kilobytes of bz2 can claim a gigabyte of memory.
:func:`install` (idempotent, done on import) puts bounded decompressors in their place; each
stops as soon as its output passes the limit of the running context (:func:`decompression_limit`,
default :data:`DEFAULT_LIMIT_BYTES`) and raises :class:`DecompressionLimitError`.

>>> import bz2
>>> with decompression_limit(1000):
...     bounded_bz2(bz2.compress(b"\\0" * 1000)) == b"\\0" * 1000
True
>>> with decompression_limit(999):
...     bounded_bz2(bz2.compress(b"\\0" * 1000))
Traceback (most recent call last):
...
episodes.bag_limits.DecompressionLimitError: a bz2 block expands past the limit of 999 bytes
"""

import bz2
import contextvars
import io
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from typing import Any, Protocol

import lz4.frame  # type: ignore[import-untyped]

try:
    from compression import zstd  # type: ignore[import-not-found,unused-ignore]
except ImportError:  # before Python 3.14
    from backports import zstd  # type: ignore[no-redef,unused-ignore]

from episodes.errors import EpisodeError
from kg import errors as kinds

__all__ = [
    "DEFAULT_LIMIT_BYTES",
    "DamagedBagError",
    "DecompressionLimitError",
    "bounded_bz2",
    "bounded_lz4",
    "bounded_zstd",
    "decompression_limit",
    "install",
]

DEFAULT_LIMIT_BYTES = 512 * 1024**2
"""The limit outside :func:`decompression_limit`."""

_LIMIT: contextvars.ContextVar[int] = contextvars.ContextVar(
    "decompression_limit", default=DEFAULT_LIMIT_BYTES
)


class DamagedBagError(EpisodeError, kinds.InvalidInputError):
    """A compressed piece of a bag cannot be decompressed."""


class DecompressionLimitError(DamagedBagError):
    """A compressed piece of a bag expands past the decompression limit."""


class _Decompressor(Protocol):
    @property
    def eof(self) -> bool: ...
    @property
    def unused_data(self) -> bytes: ...
    def decompress(self, data: bytes, max_length: int = ...) -> bytes: ...


@contextmanager
def decompression_limit(limit_bytes: int) -> Iterator[None]:
    """Bound every decompression in this context (thread, task) to ``limit_bytes``."""
    if limit_bytes <= 0:
        raise ValueError(f"limit_bytes: got {limit_bytes}, expected a positive number of bytes")
    token = _LIMIT.set(limit_bytes)
    try:
        yield
    finally:
        _LIMIT.reset(token)


def _bounded(make: Callable[[], _Decompressor], data: bytes, what: str) -> bytes:
    """Every frame of ``data`` decompressed, stopping once the output passes the limit."""
    limit = _LIMIT.get()
    out: list[bytes] = []
    total = 0
    remaining = memoryview(data).tobytes() if not isinstance(data, bytes) else data
    while True:
        decompressor = make()
        try:
            piece = decompressor.decompress(remaining, max_length=limit - total + 1)
        except (OSError, ValueError, RuntimeError, EOFError) as error:
            raise DamagedBagError(f"a {what} block is damaged ({error})") from None
        total += len(piece)
        if total > limit:
            raise DecompressionLimitError(f"a {what} block expands past the limit of {limit} bytes")
        out.append(piece)
        if not decompressor.eof:
            raise DamagedBagError(f"a {what} block ends before its compressed stream does")
        remaining = decompressor.unused_data
        if not remaining:
            return b"".join(out)


def bounded_bz2(data: bytes) -> bytes:
    """``bz2.decompress`` within the limit."""
    return _bounded(bz2.BZ2Decompressor, data, "bz2")


def bounded_lz4(data: bytes) -> bytes:
    """``lz4.frame.decompress`` within the limit."""
    return _bounded(lz4.frame.LZ4FrameDecompressor, data, "lz4")


def bounded_zstd(data: bytes) -> bytes:
    """``zstd.decompress`` within the limit."""
    return _bounded(zstd.ZstdDecompressor, data, "zstd")


class _BoundedReader(io.RawIOBase):
    """A readable stream that raises once more than the limit has been read from it."""

    def __init__(self, inner: Any) -> None:
        self.inner = inner
        self.limit = _LIMIT.get()
        self.total = 0

    def readable(self) -> bool:
        return True

    def readinto(self, buffer: Any) -> int:
        data = self.inner.read(len(buffer))
        self.total += len(data)
        if self.total > self.limit:
            raise DecompressionLimitError(
                f"a zstd-compressed bag file expands past the limit of {self.limit} bytes"
            )
        buffer[: len(data)] = data
        return len(data)

    def close(self) -> None:
        self.inner.close()
        super().close()


class _BoundedZstd:
    """What ``rosbags.rosbag2.reader`` uses of the ``zstd`` module, bounded."""

    ZstdError = getattr(zstd, "ZstdError", ValueError)

    @staticmethod
    def decompress(data: bytes) -> bytes:
        return bounded_zstd(data)

    @staticmethod
    def open(file: Any, mode: str = "rb", **kwargs: Any) -> Any:
        inner = zstd.open(file, mode, **kwargs)
        return _BoundedReader(inner) if "r" in mode else inner


def install() -> None:
    """Put the bounded decompressors into ``rosbags``' readers (again: no change)."""
    from rosbags.rosbag1 import reader as ros1
    from rosbags.rosbag2 import reader as ros2
    from rosbags.rosbag2 import storage_mcap

    ros1.decompressors["bz2"] = bounded_bz2
    ros1.decompressors["lz4"] = bounded_lz4
    ros2.zstd = _BoundedZstd  # type: ignore[attr-defined,assignment]
    storage_mcap.DECOMPRESSORS["lz4"] = lambda data, _size: bounded_lz4(data)
    storage_mcap.DECOMPRESSORS["zstd"] = lambda data, _size: bounded_zstd(data)


install()
