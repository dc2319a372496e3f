"""RangedFile: a seekable file over ranged reads, reading ahead only for a forward reader."""

import pytest

from episodes.streams import CorruptRecordingError
from episodes.streams.ranged import RangedFile

DATA = bytes(range(256)) * 8192  # 2 MiB


def _file(**options: object) -> tuple[RangedFile, list[tuple[int, int]]]:
    asked: list[tuple[int, int]] = []

    def read(start: int, length: int) -> bytes:
        asked.append((start, length))
        return DATA[start : start + length]

    return RangedFile(read, len(DATA), name="x", **options), asked  # type: ignore[arg-type]


def test_a_read_elsewhere_fetches_exactly_what_is_asked() -> None:
    file, asked = _file()
    file.seek(1000)
    assert file.read(10) == DATA[1000:1010]
    file.seek(500_000)
    assert file.read(300_000) == DATA[500_000:800_000]
    assert asked == [(1000, 10), (500_000, 300_000)]


def test_a_forward_reader_reads_ahead_twice_as_far_each_time() -> None:
    file, asked = _file(ahead_bytes=1000, max_ahead_bytes=4000)
    file.read(10)
    for _ in range(4):
        start, length = asked[-1]
        file.seek(start + length + 50)  # past what it holds, a little (message indexes)
        assert file.read(10) == DATA[file.tell() - 10 : file.tell()]
    assert [length for _, length in asked] == [10, 1000, 2000, 4000, 4000]
    file.seek(0)  # backwards: exactly what is asked again
    file.read(10)
    assert asked[-1] == (0, 10)


def test_known_parts_are_not_fetched_and_a_short_read_is_corrupt() -> None:
    file, asked = _file(known=[(0, DATA[:8]), (len(DATA) - 100, DATA[-100:])])
    assert file.read(8) == DATA[:8]
    file.seek(-100, 2)
    assert file.read() == DATA[-100:]
    assert asked == []
    short = RangedFile(lambda start, length: b"x", 100, name="s3://b/o.mcap")
    with pytest.raises(CorruptRecordingError, match=r"s3://b/o\.mcap: read 1 bytes at offset 0"):
        short.read(10)
