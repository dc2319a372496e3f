"""Every file Engram writes (``episodes.streams.bagwrite`` over ``mcapwrite``): read by the
official reader with CRC validation, by rosbags and by our reader, with CRCs on the chunks, the
data section and the summary, so a flipped byte is a ``CorruptRecordingError``, never different
data; and ``McapWriter`` writes the bytes the ``mcap`` package's writer writes."""

import io
import struct
from collections.abc import Callable
from pathlib import Path

import numpy as np
import pytest
from mcap.reader import make_reader
from mcap.records import Channel, Chunk, DataEnd, Footer, Message, Schema
from mcap.stream_reader import StreamReader
from mcap.writer import CompressionType, Writer
from rosbags.highlevel import AnyReader

from episodes.streams import CorruptRecordingError, Recorder, Replayer, export_bag, recover
from episodes.streams.bagwrite import mcap_file
from episodes.streams.foxglove import add_scene_channel, scene_entity, scene_message
from episodes.streams.mcapread import McapFile
from episodes.streams.mcapwrite import McapWriter
from kg.primitive import Primitive

T0 = 1_700_000_000_000_000_000
LIBRARY_COMPRESSIONS = {
    None: CompressionType.NONE,
    "zstd": CompressionType.ZSTD,
    "lz4": CompressionType.LZ4,
}
MESSAGE = "do not match their CRC"
BALL = Primitive("ball", "Sphere", centre=(0.0, 0.0, 0.05), radius=0.05)


def record(path: Path, frames: int = 9, **options: object) -> list[np.ndarray]:
    """Images (each larger than a chunk's worth of joints) on every other tick, joints on all,
    and a provider that joins mid-recording."""
    rng = np.random.default_rng(7)
    images = [rng.integers(0, 256, (240, 320, 3), dtype=np.uint8) for _ in range(frames)]
    recorder = Recorder(path, episode_id=path.name, **options)  # type: ignore[arg-type]
    recorder.add_provider("cam", "image", encoding="rgb8")
    recorder.add_provider("joints", "joint_state", names=["a", "b"])
    for k, image in enumerate(images):
        samples = {"joints": [k * 0.1, -k * 0.1]}
        if k % 2 == 0:
            samples["cam"] = image
        recorder.tick(samples, time_ns=T0 + k * 10_000_000)
        if k == 3:
            recorder.add_provider("late", "image", encoding="rgb8")
            recorder.tick({"late": image}, time_ns=T0 + k * 10_000_000 + 1)
    recorder.close()
    return images


def scenes(bag: Path) -> None:
    times = [T0 + 15_000_000, T0 + 10**9]  # among the samples, and after the last
    add_scene_channel(
        bag,
        [(t, scene_message(scene_entity("s", [BALL], time_ns=t))) for t in times],
        episode_id=bag.name,
    )


def recorded(tmp: Path) -> Path:
    record(tmp / "plain")
    return tmp / "plain"


def zstd(tmp: Path) -> Path:
    record(tmp / "zstd", compression="zstd")
    return tmp / "zstd"


def lz4(tmp: Path) -> Path:
    record(tmp / "lz4", compression="lz4")
    return tmp / "lz4"


def with_scenes(tmp: Path) -> Path:
    record(tmp / "scenes", compression="zstd")
    scenes(tmp / "scenes")
    return tmp / "scenes"


def scenes_only(tmp: Path) -> Path:
    scenes(tmp / "only")
    return tmp / "only"


def exported(tmp: Path) -> Path:
    record(tmp / "source")
    export_bag(tmp / "source", tmp / "exported")
    return tmp / "exported"


def recovered(tmp: Path) -> Path:
    record(tmp / "cut")
    file = mcap_file(tmp / "cut")
    with file.open("r+b") as stream:
        summary = make_reader(stream).get_summary()
        assert summary is not None
        last = summary.chunk_indexes[-1]
        # a crash after the last chunk: no metadata, no summary, no footer
        stream.truncate(last.chunk_start_offset + last.chunk_length + last.message_index_length)
    (tmp / "cut" / "metadata.yaml").unlink()
    recover(tmp / "cut")
    return tmp / "cut"


WRITTEN: list[Callable[[Path], Path]] = [
    recorded,
    zstd,
    lz4,
    with_scenes,
    scenes_only,
    exported,
    recovered,
]


@pytest.mark.parametrize("write", WRITTEN, ids=[w.__name__ for w in WRITTEN])
def test_every_file_we_write_passes_every_reader_with_crcs(
    tmp_path: Path, write: Callable[[Path], Path]
) -> None:
    bag = write(tmp_path)
    file = mcap_file(bag)

    with file.open("rb") as stream:
        reader = make_reader(stream, validate_crcs=True)
        summary = reader.get_summary()
        assert summary is not None and summary.statistics is not None
        official = [(c.topic, m.log_time, m.data) for _, c, m in reader.iter_messages()]
        assert summary.statistics.message_count == len(official)
        assert summary.chunk_indexes and all(c.message_index_offsets for c in summary.chunk_indexes)
    with file.open("rb") as stream:  # forward, every record, every CRC checked
        records = list(StreamReader(stream, skip_magic=False, validate_crcs=True).records)
    assert all(r.uncompressed_crc != 0 for r in records if isinstance(r, Chunk))
    assert [r.data_section_crc != 0 for r in records if isinstance(r, DataEnd)] == [True]
    assert [r.summary_crc != 0 for r in records if isinstance(r, Footer)] == [True]

    ours = [(m.topic, m.log_time, bytes(m.data)) for m in McapFile.open(file).messages()]
    assert sorted(ours) == sorted(official)
    logged = [t for _, t, _ in ours]
    assert logged == sorted(logged)  # in file order, log times never go backwards

    with AnyReader([bag]) as rosbag:
        assert rosbag.message_count == len(official)
        assert sorted((c.topic, t, bytes(raw)) for c, t, raw in rosbag.messages()) == sorted(
            official
        )


def test_large_samples_read_back_the_same(tmp_path: Path) -> None:
    images = record(tmp_path / "big", frames=9)
    replayed = list(Replayer(tmp_path / "big").frames())
    cams = [f.samples["cam"].value for f in replayed if "cam" in f.samples]
    assert len(cams) == 5
    for k, value in enumerate(cams):
        assert np.array_equal(value, images[2 * k])
    late = [f.samples["late"].value for f in replayed if "late" in f.samples]
    assert len(late) == 1 and np.array_equal(late[0], images[3])


def test_images_get_chunks_of_their_own(tmp_path: Path) -> None:
    """So a reader of the joints (a plot, replay of some channels from storage) skips them."""
    record(tmp_path / "big", frames=9)
    with mcap_file(tmp_path / "big").open("rb") as stream:
        summary = make_reader(stream).get_summary()
    assert summary is not None
    topics = {c.id: c.topic for c in summary.channels.values()}
    held = [{topics[c] for c in i.message_index_offsets} for i in summary.chunk_indexes]
    assert sum(1 for h in held if h & {"/cam", "/late"}) == 5 + 1
    assert all(h in ({"/cam"}, {"/late"}) for h in held if h & {"/cam", "/late"})


def _first_image_byte(file: Path) -> int:
    """The offset of a byte in the middle of the first image's pixels."""
    data = file.read_bytes()
    header = struct.pack("<II", 240, 320)  # sensor_msgs/Image: height, width
    at = data.index(header)
    return at + 1000


@pytest.mark.parametrize("write", [recorded, with_scenes], ids=["recorded", "with scenes"])
def test_a_flipped_byte_is_a_corrupt_recording_not_other_data(
    tmp_path: Path, write: Callable[[Path], Path]
) -> None:
    bag = write(tmp_path)
    file = mcap_file(bag)
    # compressed: a byte inside the first chunk's data; else one of the first image's pixels
    offset = file.stat().st_size // 3 if write is with_scenes else _first_image_byte(file)
    data = bytearray(file.read_bytes())
    data[offset] ^= 0x01
    file.write_bytes(bytes(data))

    with pytest.raises(CorruptRecordingError, match=MESSAGE):
        list(McapFile.open(file).messages())
    with pytest.raises(CorruptRecordingError):
        list(Replayer(bag).frames())


@pytest.mark.parametrize("compression", [None, "zstd", "lz4"])
@pytest.mark.parametrize("seed", [1, 2, 3])
def test_the_writer_writes_the_bytes_the_library_writes(compression: str | None, seed: int) -> None:
    """Schemas and channels declared along the way, messages from empty to several chunks
    long, metadata, flushes: ``McapWriter`` and ``mcap.writer.Writer`` write the same bytes."""
    rng = np.random.default_rng(seed)
    ours_out, theirs_out = io.BytesIO(), io.BytesIO()
    ours = McapWriter(ours_out, compression=compression, chunk_bytes=4096, profile="ros2")
    theirs = Writer(
        theirs_out,
        chunk_size=4096,
        compression=LIBRARY_COMPRESSIONS[compression],
        enable_crcs=True,
        enable_data_crcs=True,
    )
    theirs.start(profile="ros2")
    channels: list[int] = []
    log_time = 1_000
    for step in range(200):
        roll = rng.random()
        if not channels or roll < 0.05:
            name = f"pkg/msg/T{len(channels)}"
            definition = rng.bytes(int(rng.integers(0, 300)))
            schema = ours.register_schema(name, "ros2msg", definition)
            assert theirs.register_schema(name, "ros2msg", definition) == schema
            topic, metadata = f"/t{len(channels)}", {"offered_qos_profiles": "[]"}
            channel = ours.register_channel(topic, "cdr", schema, metadata)
            assert theirs.register_channel(topic, "cdr", schema, metadata) == channel
            channels.append(channel)
        elif roll < 0.08:
            ours.flush()
            theirs.flush()  # type: ignore[no-untyped-call]
        elif roll < 0.1:
            ours.add_metadata(f"m{step}", {"key": str(step)})
            theirs.add_metadata(f"m{step}", {"key": str(step)})
        else:
            size = int(rng.choice([0, 10, 300, 5000, 20_000]))
            data = memoryview(rng.bytes(size))
            channel = channels[int(rng.integers(len(channels)))]
            log_time += int(rng.integers(0, 3))
            ours.add_message(channel, log_time, data, log_time + 1)
            theirs.add_message(channel, log_time, bytes(data), log_time + 1)
    ours.finish()
    theirs.finish()  # type: ignore[no-untyped-call]
    assert ours_out.getvalue() == theirs_out.getvalue()


SUITE_FILES = sorted(
    (Path(__file__).parent / "conformance" / "data").rglob("*.mcap")
)  # the MCAP conformance suite (test_mcap_conformance.py)


def test_the_suite_s_contents_rewritten_are_the_library_s_bytes_and_read_back() -> None:
    """Each conformance file's schemas, channels and messages, written again by ``McapWriter``
    and by the library's ``Writer``: the same bytes, and the same messages read back."""
    assert len(SUITE_FILES) == 416
    for path in SUITE_FILES:
        with path.open("rb") as stream:
            records = list(StreamReader(stream, skip_magic=False).records)
        outputs = []
        for make in (_ours, _theirs):
            out = io.BytesIO()
            writer = make(out)
            schemas: dict[int, int] = {0: 0}
            channels: dict[int, int] = {}
            for record in records:
                if isinstance(record, Schema) and record.id not in schemas:
                    schemas[record.id] = writer.register_schema(
                        record.name, record.encoding, record.data
                    )
                elif isinstance(record, Channel) and record.id not in channels:
                    channels[record.id] = writer.register_channel(
                        record.topic,
                        record.message_encoding,
                        schemas[record.schema_id],
                        record.metadata,
                    )
                elif isinstance(record, Message):
                    writer.add_message(
                        channels[record.channel_id],
                        record.log_time,
                        record.data,
                        record.publish_time,
                    )
            writer.finish()
            outputs.append(out.getvalue())
        assert outputs[0] == outputs[1], path.name
        read = make_reader(io.BytesIO(outputs[0]), validate_crcs=True)
        again = [(m.log_time, m.data) for _, _, m in read.iter_messages(log_time_order=False)]
        assert again == [(m.log_time, m.data) for m in records if isinstance(m, Message)], path


def _ours(out: io.BytesIO) -> McapWriter:
    return McapWriter(out, compression="zstd", chunk_bytes=64)


def _theirs(out: io.BytesIO) -> Writer:
    writer = Writer(
        out,
        chunk_size=64,
        compression=CompressionType.ZSTD,
        enable_crcs=True,
        enable_data_crcs=True,
    )
    writer.start()
    return writer
