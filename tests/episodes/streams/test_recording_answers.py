"""What the stream endpoints answer for a recording that holds nothing (it replays and exports
as empty, issue 29 item 7) and for a damaged one (409 naming the file and the offset)."""

import io
import tarfile
from pathlib import Path

import numpy as np
from rosbags.highlevel import AnyReader

from episodes.streams.wire import encode_value
from tests.conftest import LiveServer


def test_an_empty_recording_replays_and_exports_as_empty(
    live_server: LiveServer, tmp_path: Path
) -> None:
    client = live_server.client
    client.post("/episodes", json={"activity": "idle", "id": "ep-empty", "record": True})
    assert client.post("/episodes/ep-empty/end", json={}).status_code == 200

    info = client.get("/episodes/ep-empty/streams")
    assert info.status_code == 200, info.text
    assert (info.json()["frames"], info.json()["complete"]) == (0, True)
    replay = client.get("/episodes/ep-empty/streams/replay")
    assert (replay.status_code, replay.text) == (200, "")

    for query in ("", "?with_runs=true"):
        export = client.get(f"/episodes/ep-empty/streams/export{query}")
        assert export.status_code == 200, export.text
        target = tmp_path / (query or "plain")
        with tarfile.open(fileobj=io.BytesIO(export.content)) as tar:
            tar.extractall(target, filter="data")
        with AnyReader([target / "ep-empty"]) as reader:
            assert list(reader.messages()) == []


def test_a_run_whose_samples_were_refused_exports_with_the_recording(
    live_server: LiveServer, tmp_path: Path
) -> None:
    client = live_server.client
    client.post("/episodes", json={"activity": "idle", "id": "ep-run", "record": True})
    provider = {"name": "arm", "kind": "float_array", "shape": [2]}
    assert client.post("/episodes/ep-run/streams/providers", json=provider).status_code == 201
    ticks = [{"time_ns": 1_000 + i, "samples": {"arm": [i, i]}} for i in range(3)]
    assert client.post("/episodes/ep-run/streams/samples", json={"ticks": ticks}).status_code == 200
    assert client.post("/episodes/ep-run/end", json={}).status_code == 200
    run = client.post("/episodes/ep-run/runs", json={"name": "pose", "producer": "p"}).json()
    sample = {"frame": 2, "source_channel": "arm", "derived_channel": "pose"}
    refused = client.post(  # no such kind: refused, after the run's file was opened
        f"/episodes/ep-run/runs/{run['id']}/samples",
        json={
            "samples": [{**sample, "value": encode_value(np.array([1.0, 2.0]))}],
            "channels": {"pose": {"kind": "smell"}},
        },
    )
    assert refused.status_code == 422, refused.text
    client.post(f"/episodes/ep-run/runs/{run['id']}/end")

    export = client.get("/episodes/ep-run/streams/export?with_runs=true")
    assert export.status_code == 200, export.text
    with tarfile.open(fileobj=io.BytesIO(export.content)) as tar:
        tar.extractall(tmp_path, filter="data")
    with AnyReader([tmp_path / "ep-run"]) as reader:
        topics = {c.topic for c in reader.connections}
        assert "/arm" in topics
        assert sum(1 for c, _, _ in reader.messages() if c.topic == "/arm") == 3


def test_a_damaged_recording_answers_409_naming_file_and_offset(live_server: LiveServer) -> None:
    client = live_server.client
    client.post("/episodes", json={"activity": "idle", "id": "ep-bad", "record": True})
    provider = {"name": "arm", "kind": "float_array", "shape": [2]}
    assert client.post("/episodes/ep-bad/streams/providers", json=provider).status_code == 201
    ticks = [{"time_ns": 1_000 + i, "samples": {"arm": [i, i]}} for i in range(3)]
    assert client.post("/episodes/ep-bad/streams/samples", json={"ticks": ticks}).status_code == 200
    assert client.post("/episodes/ep-bad/end", json={}).status_code == 200
    file = live_server.settings.data_dir / "streams" / "ep-bad" / "ep-bad.mcap"
    data = bytearray(file.read_bytes())
    footer = len(data) - 8 - 29
    data[footer + 9 : footer + 17] = (len(data) * 2).to_bytes(8, "little")  # summary start
    file.write_bytes(bytes(data))

    for path in (
        "/episodes/ep-bad/streams/replay",
        "/episodes/ep-bad/streams/export",
        "/views/episodes/ep-bad/plot?channel=arm",
        "/views/episodes/ep-bad/channels",
    ):
        answer = client.get(path)
        assert answer.status_code == 409, (path, answer.text)
        assert answer.json()["error"] == "CorruptRecordingError"
        assert "ep-bad.mcap" in answer.json()["detail"]
        assert f"at offset {footer}" in answer.json()["detail"]
