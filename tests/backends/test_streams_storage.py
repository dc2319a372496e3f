"""Recordings on a real S3-compatible server (moto on loopback): an ended episode's MCAP goes up
write-once with its URI, size and SHA-256 in the graph; replay and export fetch it back; deleting
the episode deletes its objects."""

import base64
import hashlib
import io
import json
import tarfile
import uuid
from pathlib import Path
from typing import Any

import boto3
import numpy as np
import pytest

from episodes.streams.objects import ObjectStorageError, ObjectStore, StoredObject
from episodes.streams.wire import BATCH_MEDIA_TYPE, encode_batch
from tests.backends.servers import MotoServer
from tests.conftest import LiveServer

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


def _array(value: dict[str, Any]) -> np.ndarray:
    raw = base64.b64decode(value["b64"])
    return np.frombuffer(raw, dtype=value["dtype"]).reshape(value["shape"])


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
    replayed = [_array(f["samples"][0]["value"]["position"]) for f in frames]
    assert [r.tobytes() for r in replayed] == [s.tobytes() for s in sent]  # bit-exact
    assert local.is_dir()  # fetched into the local cache

    tar = server.client.get("/episodes/ep1/streams/export")
    assert tar.status_code == 200
    with tarfile.open(fileobj=io.BytesIO(tar.content)) as exported:
        assert any(name.endswith(".mcap") for name in exported.getnames())

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
