"""Recordings on a real S3-compatible server (moto on loopback): an ended episode's MCAP goes up
write-once with its URI, size and SHA-256 in the graph; replay reads it in place by ranges, export
fetches it back into a size-bounded cache; deleting the episode deletes its objects."""

import hashlib
import io
import json
import os
import tarfile
import uuid
from pathlib import Path

import boto3
import numpy as np
import pytest

from episodes.archive import FETCHED_MARK, StreamArchive
from episodes.streams import Recorder, Replayer
from episodes.streams.objects import ObjectStorageError, ObjectStore, StoredObject
from episodes.streams.ranged import open_ranged
from episodes.streams.wire import BATCH_MEDIA_TYPE, encode_batch
from kg import Store
from tests.backends.servers import MotoServer
from tests.conftest import LiveServer, wire_array

pytestmark = pytest.mark.slow

T0 = 1_769_441_400_000_000_000
OBJECTS = """
PREFIX engram: <https://w3id.org/engram/ontology#>
SELECT ?object ?size ?sha256 ?descriptor WHERE {
  ?episode engram:streamObject ?object .
  ?object engram:byteSize ?size ; engram:sha256 ?sha256 .
  OPTIONAL { ?descriptor engram:streamObject ?object ; a engram:StreamDescriptor }
}
"""


@pytest.fixture
def bucket(s3_server: MotoServer) -> str:
    name = f"engram-{uuid.uuid4().hex[:12]}"
    boto3.client("s3", endpoint_url=s3_server.url).create_bucket(Bucket=name)
    return name


def _record(server: LiveServer, episode: str, ticks: int) -> list[np.ndarray]:
    client = server.client
    begun = client.post(
        "/episodes",
        json={
            "activity": "babbling",
            "id": episode,
            "record": True,
            "begin": "2026-01-26T15:30:00+00:00",
        },
    )
    assert begun.status_code == 201, begun.text
    provider = {"name": "icub/joints", "kind": "joint_state", "names": ["a", "b"]}
    assert client.post(f"/episodes/{episode}/streams/providers", json=provider).status_code == 201
    rng = np.random.default_rng(3)
    sent = [rng.normal(size=2) for _ in range(ticks)]
    batch = [
        {"time_ns": T0 + i * 10_000_000, "samples": {"icub/joints": value}}
        for i, value in enumerate(sent)
    ]
    answer = client.post(
        f"/episodes/{episode}/streams/samples",
        content=encode_batch(batch),
        headers={"content-type": BATCH_MEDIA_TYPE},
    )
    assert answer.status_code == 200, answer.text
    ended = client.post(f"/episodes/{episode}/end", json={"end": "2026-01-26T15:30:01+00:00"})
    assert ended.status_code == 200, ended.text
    return sent


def test_an_ended_episode_round_trips_through_object_storage_and_is_deleted_with_it(
    s3_server: MotoServer,
    bucket: str,
    start_server,
    tmp_path: Path,  # type: ignore[no-untyped-def]
) -> None:
    server: LiveServer = start_server(
        streams_url=f"s3://{bucket}/robot-a", streams_endpoint=s3_server.url
    )
    sent = _record(server, "ep1", 20)
    local = server.settings.data_dir / "streams" / "ep1"
    assert not local.exists()  # moved off the robot's disk

    rows = server.client.get(
        "/sparql",
        params={"query": OBJECTS},
        headers={"Accept": "application/sparql-results+json"},
    ).json()["results"]["bindings"]
    mcap = [r for r in rows if r["object"]["value"].endswith(".mcap")]
    assert mcap and all("descriptor" in r for r in mcap)
    uri = mcap[0]["object"]["value"]
    assert uri.startswith(f"s3://{bucket}/robot-a/ep1/")
    s3 = boto3.client("s3", endpoint_url=s3_server.url)
    body = s3.get_object(Bucket=bucket, Key=uri.split("/", 3)[3])["Body"].read()
    assert int(mcap[0]["size"]["value"]) == len(body)
    assert mcap[0]["sha256"]["value"] == hashlib.sha256(body).hexdigest()

    frames = [
        json.loads(line)
        for line in server.client.get("/episodes/ep1/streams/replay").text.splitlines()
    ]
    replayed = [wire_array(f["samples"][0]["value"]["position"]) for f in frames]
    assert [r.tobytes() for r in replayed] == [s.tobytes() for s in sent]  # bit-exact
    assert not local.exists()  # replayed by ranged reads, not fetched

    tar = server.client.get("/episodes/ep1/streams/export")
    assert tar.status_code == 200
    with tarfile.open(fileobj=io.BytesIO(tar.content)) as exported:
        assert any(name.endswith(".mcap") for name in exported.getnames())
    assert (local / FETCHED_MARK).exists()  # export fetched it into the local cache

    assert server.client.delete("/episodes/ep1").status_code in (200, 204)
    listed = s3.list_objects_v2(Bucket=bucket, Prefix="robot-a/ep1/")
    assert listed.get("KeyCount", 0) == 0


def test_an_object_is_written_once(s3_server: MotoServer, bucket: str, tmp_path: Path) -> None:
    store = ObjectStore(f"s3://{bucket}/p", endpoint_url=s3_server.url)
    first, second = tmp_path / "a", tmp_path / "b"
    first.write_bytes(b"one")
    second.write_bytes(b"two")
    stored = store.upload(first, "ep/file.mcap")
    assert store.upload(first, "ep/file.mcap") == stored  # repeated after a crash: accepted
    with pytest.raises(ObjectStorageError, match="already exists"):
        store.upload(second, "ep/file.mcap")
    assert store.fetch(stored, tmp_path / "back").read_bytes() == b"one"


def test_a_fetch_that_does_not_match_its_digest_leaves_nothing(
    s3_server: MotoServer, bucket: str, tmp_path: Path
) -> None:
    store = ObjectStore(f"s3://{bucket}/p", endpoint_url=s3_server.url)
    source = tmp_path / "a"
    source.write_bytes(b"payload")
    stored = store.upload(source, "ep/f")
    forged = StoredObject(stored.uri, stored.size, "0" * 64)
    with pytest.raises(ObjectStorageError, match="do not match"):
        store.fetch(forged, tmp_path / "out" / "f")
    assert list((tmp_path / "out").iterdir()) == []


def _camera_recording(path: Path, frames: int, compression: str | None) -> None:
    recorder = Recorder(path, episode_id=path.name, compression=compression)
    recorder.add_provider("cam", "image", encoding="rgb8")
    recorder.add_provider("joints", "float_array", dtype="float64")
    rng = np.random.default_rng(7)
    for i in range(frames):
        image = rng.integers(0, 256, (240, 320, 3), dtype=np.uint8)
        recorder.tick({"cam": image, "joints": np.arange(3.0) * i}, time_ns=(i + 1) * 33_000_000)
    recorder.close()


def _samples(replayer: Replayer, channels: list[str] | None = None) -> list[tuple[int, bytes]]:
    return [
        (frame.number, b"".join(np.asarray(s.value).tobytes() for s in frame.samples.values()))
        for frame in replayer.frames(channels)
    ]


@pytest.mark.parametrize("compression", [None, "zstd"])
def test_replay_reads_a_stored_recording_by_ranges(
    s3_server: MotoServer, bucket: str, tmp_path: Path, compression: str | None
) -> None:
    bag = tmp_path / "ep-ranged"
    _camera_recording(bag, 40, compression)
    store = ObjectStore(f"s3://{bucket}/robot", endpoint_url=s3_server.url)
    (stored,) = [s for s in store.upload_directory(bag, "ep-ranged") if s.name.endswith(".mcap")]
    local = Replayer(bag)

    read: list[int] = []

    def ranged(start: int, n: int) -> bytes:
        read.append(n)
        return store.read_range(stored.uri, start, n)

    remote = Replayer(stored.uri, scan=open_ranged(ranged, stored.size, name=stored.uri))
    assert (remote.episode_id, remote.ticks) == (local.episode_id, local.ticks)
    read.clear()
    assert _samples(remote, ["joints"]) == _samples(local, ["joints"])
    if compression is None:  # images in chunks of their own: read the joints' chunks only
        assert sum(read) < stored.size // 10
    local.seek(frame=25)
    remote.seek(frame=25)
    assert _samples(remote) == _samples(local)


def test_fetched_recordings_are_evicted_least_recently_used_first(
    tmp_path: Path, empty_store: Store
) -> None:
    root = tmp_path / "streams"
    for name, size in (("old", 400), ("new", 400), ("recorded", 4000)):
        (root / name).mkdir(parents=True)
        (root / name / f"{name}.mcap").write_bytes(b"x" * size)
    (root / "old" / FETCHED_MARK).touch()
    (root / "new" / FETCHED_MARK).touch()
    objects = ObjectStore("s3://engram-unused/p", endpoint_url="http://127.0.0.1:9")
    archive = StreamArchive(objects, root, cache_bytes=500)
    older = (root / "new" / FETCHED_MARK).stat().st_mtime - 60
    os.utime(root / "new" / FETCHED_MARK, (older, older))
    assert archive.local(empty_store, "old") == root / "old"  # a use: "new" is now older
    assert archive.evict() == [root / "new"]
    assert sorted(p.name for p in root.iterdir()) == ["old", "recorded"]  # never a recording
    with pytest.raises(ValueError, match="cache_bytes"):
        StreamArchive(objects, root, cache_bytes=-1)


class _CountedReads(ObjectStore):
    reads = 0

    def read_range(self, uri: str, start: int, length: int) -> bytes:
        self.reads += 1
        return super().read_range(uri, start, length)


def test_an_archived_recording_opens_for_replay_with_a_few_reads(
    s3_server: MotoServer, bucket: str, tmp_path: Path, empty_store: Store
) -> None:
    root = tmp_path / "streams"
    _camera_recording(root / "ep-few", 40, None)
    local = Replayer(root / "ep-few")
    expected = (local.ticks, _samples(local))
    objects = _CountedReads(f"s3://{bucket}/robot", endpoint_url=s3_server.url)
    archive = StreamArchive(objects, root)
    names = sorted(s.name for s in archive.archive(empty_store, "ep-few"))
    assert names == ["ep-few.mcap", "ep-few.replay-messages", "metadata.yaml"]
    assert not (root / "ep-few").exists()

    replayer = archive.replayer(empty_store, "ep-few")
    next(iter(replayer.frames()))
    assert objects.reads == 2  # the saved messages and summary, then the first chunk
    assert (replayer.ticks, _samples(replayer)) == expected
    assert not (root / "ep-few").exists()  # read in place


def test_a_recording_cut_short_is_read_by_ranges_up_to_its_last_record(tmp_path: Path) -> None:
    _camera_recording(tmp_path / "ep-cut", 10, None)
    data = next((tmp_path / "ep-cut").glob("*.mcap")).read_bytes()
    cut = data[: len(data) // 2]  # a crash: no summary, no footer
    (tmp_path / "cut.mcap").write_bytes(cut)
    local = Replayer(tmp_path / "cut.mcap")
    scan = open_ranged(lambda start, n: cut[start : start + n], len(cut), name="cut.mcap")
    remote = Replayer("cut.mcap", scan=scan)
    assert not remote.complete and 0 < remote.frame_count < 10
    assert (remote.ticks, _samples(remote)) == (local.ticks, _samples(local))
