"""Every MCAP reader of the recorder answers right on the MCAP conformance suite (416 files
covering every writer option) and, on damaged files and decompression bombs, answers
:class:`CorruptRecordingError` naming the file and the offset, with bounded memory."""

import contextlib
import hashlib
import io
import json
import tracemalloc
import zlib
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any

import lz4.frame
import numpy as np
import pytest
from mcap.data_stream import RecordBuilder
from mcap.records import Channel, Chunk, DataEnd, Footer, Header, McapRecord, Message, Schema

from api.views import series
from episodes.streams import CorruptRecordingError, Recorder, Replayer
from episodes.streams.bagwrite import mcap_file
from episodes.streams.mcapread import MAGIC, McapFile, RawMessage
from episodes.streams.ranged import open_ranged

try:
    from compression import zstd  # type: ignore[import-not-found,unused-ignore]
except ImportError:
    from backports import zstd  # type: ignore[import-not-found,unused-ignore,no-redef]

SUITE = Path(__file__).parent / "conformance"
FILES = sorted((SUITE / "data").rglob("*.mcap"))
Message_ = tuple[str, str, int, bytes]


def _local(path: Path) -> Iterator[RawMessage]:
    return McapFile.open(path).messages()


def _ranged(path: Path) -> Iterator[RawMessage]:
    data = path.read_bytes()
    return open_ranged(lambda s, n: data[s : s + n], len(data), name=path.name).messages()


READERS: dict[str, Callable[[Path], Iterator[RawMessage]]] = {
    "local file": _local,
    "ranged reads": _ranged,
}


def _expected(path: Path) -> list[Message_]:
    """The messages the suite's JSON lists for the file, in file order."""
    records = json.loads(path.with_suffix(".json").read_text())["records"]
    schemas: dict[str, str] = {}
    channels: dict[str, tuple[str, str]] = {}
    found = []
    for record in records:
        fields = dict(record["fields"])
        if record["type"] == "Schema":
            schemas[fields["id"]] = fields["name"]
        elif record["type"] == "Channel":
            channels[fields["id"]] = (fields["topic"], schemas.get(fields["schema_id"], ""))
        elif record["type"] == "Message":
            topic, schema = channels[fields["channel_id"]]
            data = bytes(int(b) for b in fields["data"])
            found.append((topic, schema, int(fields["log_time"]), data))
        elif record["type"] == "DataEnd":
            break  # the summary repeats schemas and channels
    return found


def _got(messages: Iterator[RawMessage]) -> list[Message_]:
    return [(m.topic, m.msgtype, m.log_time, m.data) for m in messages]


def test_the_vendored_files_are_the_upstream_suite() -> None:
    pointers = dict(
        reversed(line.split("  ")) for line in (SUITE / "lfs-sha256.txt").read_text().splitlines()
    )
    assert len(FILES) == len(pointers) == 416
    for path in FILES:
        name = str(path.relative_to(SUITE / "data"))
        assert hashlib.sha256(path.read_bytes()).hexdigest() == pointers[name], name


@pytest.mark.parametrize("reader", READERS)
def test_every_conformance_file_reads_right(reader: str) -> None:
    wrong = [p.name for p in FILES if _got(READERS[reader](p)) != _expected(p)]
    assert wrong == []


@pytest.mark.parametrize("reader", READERS)
def test_topics_and_start_time_filter_like_the_suite(reader: str) -> None:
    for path in (SUITE / "data" / "TenMessages").glob("*.mcap"):
        expected = [m for m in _expected(path) if m[2] >= 5]
        data = path.read_bytes()
        source = (
            McapFile.open(path)
            if reader == "local file"
            else open_ranged(lambda s, n, d=data: d[s : s + n], len(data), name=path.name)
        )
        assert _got(source.messages({"example"}, start_ns=5)) == expected, path.name
        assert _got(source.messages({"elsewhere"})) == [], path.name


def _listed(path: Path) -> list[tuple[str, Any]]:
    """(type, name or topic or log time) of each data-section record the suite lists."""
    found = []
    for record in json.loads(path.with_suffix(".json").read_text())["records"]:
        if record["type"] == "DataEnd":
            break
        fields = dict(record["fields"])
        key = fields.get("name", fields.get("topic", fields.get("log_time", "")))
        found.append((record["type"], str(key)))
    return found


def test_the_records_of_every_conformance_file_are_the_suites() -> None:
    def key(record: McapRecord) -> str:
        return str(
            getattr(record, "name", getattr(record, "topic", getattr(record, "log_time", "")))
        )

    wrong = [
        p.name
        for p in FILES
        if [(type(r).__name__, key(r)) for r in McapFile.open(p).records()] != _listed(p)
    ]
    assert wrong == []


def test_a_summary_without_schemas_still_names_the_type() -> None:
    # repeated channels, no repeated schemas: the type comes from the data section
    path = SUITE / "data/OneMessage/OneMessage-ch-chx-mx-pad-rch-st-sum.mcap"
    recording = McapFile.open(path)
    assert recording.summary is not None and not recording.summary.schemas
    assert [m.msgtype for m in recording.messages()] == ["Example"]


# ---------------------------------------------------------------------------- damaged files


def _record(record: McapRecord) -> bytes:
    builder = RecordBuilder()
    record.write(builder)
    data: bytes = builder.end()
    return data


def _file(*records: McapRecord, footer: Footer | None = None) -> bytes:
    """An MCAP file of ``records``, its data section CRC and a footer without summary."""
    data = MAGIC + _record(Header("", "")) + b"".join(_record(r) for r in records)
    data += _record(DataEnd(zlib.crc32(data)))
    return data + _record(footer or Footer(0, 0, 0)) + MAGIC


SCHEMA = Schema(id=1, name="Example", encoding="c", data=b"")
CHANNEL = Channel(id=1, topic="t", message_encoding="a", metadata={}, schema_id=1)


def _chunk(compression: str, data: bytes, declared: int, crc: int = 0) -> Chunk:
    return Chunk(
        compression=compression,
        data=data,
        message_start_time=1,
        message_end_time=1,
        uncompressed_crc=crc,
        uncompressed_size=declared,
    )


def _records_of_one_message(payload: bytes = b"abc") -> bytes:
    message = Message(channel_id=1, log_time=1, data=payload, publish_time=1, sequence=0)
    return _record(SCHEMA) + _record(CHANNEL) + _record(message)


def _zstd_bomb(size: int) -> bytes:
    compressor = zstd.ZstdCompressor()
    zeros = bytes(1 << 20)
    out = [compressor.compress(zeros) for _ in range(size >> 20)]
    return b"".join(out) + compressor.flush()


def _read_all(data: bytes, name: str = "damaged.mcap", **options: Any) -> list[RawMessage]:
    return list(McapFile(lambda: io.BytesIO(data), name=name, **options).messages())


@pytest.mark.parametrize(
    ("data", "fragment"),
    [
        (b"\x89MCAP1\r\n" + bytes(40), "bad magic bytes) at offset 0"),
        (_file(SCHEMA, CHANNEL, footer=Footer(10**9, 0, 0)), "outside the file"),
        (_file(Message(1, 1, b"x", 1, 0)), "undeclared channel 1"),
        (_file(_chunk("zstd", zstd.compress(b"x" * 1000), 31)), "more than the 31 bytes"),
        (_file(_chunk("lz4", lz4.frame.compress(b"x" * 1000), 31)), "more than the 31 bytes"),
        (_file(_chunk("zstd", b"garbage", 5)), "chunk"),
        (_file(_chunk("brotli", b"", 0)), "unsupported chunk compression 'brotli'"),
        (_file(_chunk("", _records_of_one_message()[:-2], 200)), "declares 200"),
        (_file(_chunk("", _records_of_one_message(), 40)), "declares 40"),
        (_file(_chunk("", _records_of_one_message(), 92, crc=7)), "CRC"),
        (_file(_chunk("zstd", b"", 2**41)), "over the limit"),
        (_file(Channel(1, "t", "a", {}, 9)), "undeclared schema 9"),
    ],
    ids=[
        "bad magic",
        "footer past the end",
        "message before its channel",
        "zstd over its declared size",
        "lz4 over its declared size",
        "zstd garbage",
        "unknown compression",
        "chunk records cut",
        "declared size wrong",
        "chunk CRC",
        "declared size over the limit",
        "channel before its schema",
    ],
)
def test_a_damaged_file_is_one_error_naming_file_and_offset(data: bytes, fragment: str) -> None:
    with pytest.raises(CorruptRecordingError, match=r"damaged\.mcap") as caught:
        _read_all(data)
    assert fragment in str(caught.value)
    assert "offset" in str(caught.value)


def test_flipped_payload_bytes_fail_the_crc() -> None:
    for path in (SUITE / "data" / "TenMessages").glob("*.mcap"):
        data = bytearray(path.read_bytes())
        at = data.index(bytes([1, 2, 3]))  # the first message's payload
        data[at] ^= 0xFF
        with pytest.raises(CorruptRecordingError, match="CRC"):
            _read_all(bytes(data))


@pytest.mark.parametrize(
    "variant",
    [
        "TenMessages",  # records in the data section, no summary
        "TenMessages-ch-chx-mx-rch-rsh-st-sum",  # one chunk, read through the summary
        "TenMessages-ch-pad",  # a chunk and padded records, read forward
    ],
)
def test_every_damaged_byte_of_a_suite_file_reads_or_is_one_error(variant: str) -> None:
    """Every byte of a file inverted, and every cut: a read gives messages or
    CorruptRecordingError, never another exception."""
    whole = (SUITE / "data" / "TenMessages" / f"{variant}.mcap").read_bytes()
    for at in range(len(whole)):
        for damaged in (whole[:at] + bytes([whole[at] ^ 0xFF]) + whole[at + 1 :], whole[:at]):
            with contextlib.suppress(CorruptRecordingError):
                _read_all(damaged)


@pytest.mark.parametrize("compression", ["zstd", "lz4"])
def test_a_decompression_bomb_is_stopped_at_its_declared_size(compression: str) -> None:
    bomb = (
        _zstd_bomb(256 << 20)
        if compression == "zstd"
        else lz4.frame.compress(bytes(256 << 20), compression_level=1)
    )
    assert len(bomb) < 2 << 20
    data = _file(_chunk(compression, bomb, 31))
    tracemalloc.start()
    try:
        with pytest.raises(CorruptRecordingError, match="more than the 31 bytes"):
            _read_all(data)
        _, peak = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()
    assert peak < 16 << 20  # the 256 MB it expands to are never held


def test_a_chunk_declaring_more_than_the_limit_is_refused_before_decompressing() -> None:
    payload = _records_of_one_message(bytes(4096))
    data = _file(_chunk("zstd", zstd.compress(payload), len(payload)))
    assert len(_read_all(data)) == 1
    with pytest.raises(CorruptRecordingError, match="over the limit 1000"):
        _read_all(data, limit_bytes=1000)


# ---------------------------------------------------------------------------- recordings


def _every_reader(path: Path) -> None:
    """Replay, plot and list the channels of the recording at ``path``, as the views do."""
    replayer = Replayer(path)
    for _ in replayer.frames():
        pass
    for channel in replayer.providers:
        series.scan_channel(path, channel)
    series.recording_times(path)
    data = path.read_bytes()
    scan = open_ranged(lambda s, n: data[s : s + n], len(data), name=path.name)
    for _ in Replayer(path.name, scan=scan).frames():
        pass


@pytest.mark.parametrize("compression", [None, "zstd"])
def test_a_damaged_recording_is_one_error_for_every_reader(
    tmp_path: Path, compression: str | None
) -> None:
    recorder = Recorder(tmp_path / "ep", episode_id="ep", compression=compression)
    recorder.add_provider("arm", "joint_state", names=["a", "b"])
    recorder.add_provider("skin", "float_array", dtype="float64", shape=[4], baseline=0.0)
    recorder.add_provider("words", "string")
    for i in range(20):
        recorder.tick(
            {"arm": {"position": np.arange(2.0) * i}, "skin": np.full(4, i % 2), "words": "hé"},
            time_ns=(i + 1) * 10_000_000,
        )
    recorder.close()
    whole = mcap_file(tmp_path / "ep").read_bytes()
    target = tmp_path / "damaged.mcap"
    rng = np.random.default_rng(28)
    for at in sorted(rng.choice(len(whole), 80, replace=False)):
        for damaged in (whole[:at] + bytes([whole[at] ^ 0xFF]) + whole[at + 1 :], whole[:at]):
            target.write_bytes(damaged)
            try:
                _every_reader(target)
            except CorruptRecordingError as error:
                assert "damaged.mcap" in str(error)
