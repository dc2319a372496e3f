"""The stream endpoints through the real server on loopback."""

import io
import json
import tarfile
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from rosbags.highlevel import AnyReader

from episodes.streams.wire import BATCH_MEDIA_TYPE, encode_batch
from tests.conftest import wire_array

T0 = 1_750_000_000_000_000_000
MS = 1_000_000
BASE = "/episodes/ep-http/streams"


def _lines(text: str) -> list[dict[str, Any]]:
    return [json.loads(line) for line in text.splitlines() if line]


@pytest.fixture
def recorded_over_http(live_server: Any) -> tuple[Any, list[dict[str, Any]]]:
    """An episode with joints, skin and two cameras recorded over HTTP, and what was sent."""
    client = live_server.client
    assert (
        client.post("/episodes", json={"activity": "babbling", "id": "ep-http"}).status_code == 201
    )
    assert client.post(BASE).status_code == 201
    providers = [
        {"name": "icub/head", "kind": "joint_state", "names": ["a", "b", "c"]},
        {"name": "icub/skin", "kind": "float_array", "shape": [16], "baseline": 5.0},
        {"name": "icub/cam/left", "kind": "image", "encoding": "rgb8"},
        {"name": "icub/cam/right", "kind": "image", "encoding": "rgb8"},
    ]
    for p in providers:
        answer = client.post(f"{BASE}/providers", json=p)
        assert answer.status_code == 201, answer.text
    rng = np.random.default_rng(3)
    sent: list[dict[str, Any]] = []
    # ticks 0-9: small samples as a JSON batch
    ticks = []
    for i in range(10):
        skin = [5.0] * 16
        if i % 4 == 0:
            skin[i] = 42.25 + i
        joints = rng.normal(size=3)
        ticks.append(
            {
                "time_ns": T0 + i * 10 * MS,
                "samples": {"icub/head": joints.tolist(), "icub/skin": skin},
            }
        )
        sent.append({"icub/head": joints, "icub/skin": np.array(skin)})
    answer = client.post(f"{BASE}/samples", json={"ticks": ticks})
    assert answer.status_code == 200, answer.text
    assert [t["frame"] for t in answer.json()["ticks"]] == list(range(1, 11))
    # ticks 10-19: joints and both cameras in a binary batch
    ticks = []
    for i in range(10, 20):
        samples = {
            "icub/head": rng.normal(size=3),
            "icub/cam/left": rng.integers(0, 256, (24, 32, 3), dtype=np.uint8),
            "icub/cam/right": rng.integers(0, 256, (24, 32, 3), dtype=np.uint8),
        }
        ticks.append(
            {
                "time_ns": T0 + i * 10 * MS,
                "samples": samples,
                "stamps_ns": {"icub/cam/left": T0 + i * 10 * MS - 3 * MS},
            }
        )
        sent.append(samples)
    answer = client.post(
        f"{BASE}/samples", content=encode_batch(ticks), headers={"content-type": BATCH_MEDIA_TYPE}
    )
    assert answer.status_code == 200, answer.text
    # tick 20: one raw image
    image = rng.integers(0, 256, (24, 32, 3), dtype=np.uint8)
    answer = client.post(
        f"{BASE}/providers/icub/cam/left/samples",
        content=image.tobytes(),
        headers={
            "x-engram-shape": "24,32,3",
            "x-engram-time-ns": str(T0 + 200 * MS),
            "content-type": "application/octet-stream",
        },
    )
    assert answer.status_code == 200, answer.text
    assert answer.json()["frame"] == 21
    sent.append({"icub/cam/left": image})
    closed = client.post(f"{BASE}/close")
    assert closed.status_code == 200, closed.text
    counts = {
        c["provider"]: (c["count_stored"], c["count_dropped"]) for c in closed.json()["channels"]
    }
    assert counts == {
        "icub/head": (20, 0),
        "icub/skin": (10, 0),
        "icub/cam/left": (11, 0),
        "icub/cam/right": (10, 0),
    }
    return live_server, sent


@pytest.mark.slow
def test_replay_frame_by_frame_is_bit_exact(recorded_over_http: tuple[Any, list[Any]]) -> None:
    server, sent = recorded_over_http
    answer = server.client.get(f"{BASE}/replay")
    assert answer.status_code == 200
    assert answer.headers["content-type"].startswith("application/x-ndjson")
    frames = _lines(answer.text)
    assert [f["frame"] for f in frames] == list(range(1, 22))
    for frame, samples in zip(frames, sent, strict=True):
        got = {s["provider"]: s for s in frame["samples"]}
        assert set(got) == set(samples)
        for name, value in samples.items():
            sample = got[name]
            assert sample["episode"] == "ep-http" and sample["frame"] == frame["frame"]
            assert sample["channel"] == "/" + name and sample["time_ns"] == frame["time_ns"]
            replayed = sample["value"]
            if name == "icub/head":
                replayed = replayed["position"]
            exact = wire_array(replayed).tobytes() == np.asarray(value).tobytes()
            assert exact, (frame["frame"], name)
    left = next(s for s in frames[12]["samples"] if s["provider"] == "icub/cam/left")
    assert left["stamp_ns"] == left["time_ns"] - 3 * MS


@pytest.mark.slow
def test_replay_in_real_time_subset_and_seek(recorded_over_http: tuple[Any, list[Any]]) -> None:
    server, _ = recorded_over_http
    answer = server.client.get(
        f"{BASE}/replay",
        params={"mode": "realtime", "speed": 4, "channels": ["icub/cam/right"], "start_frame": 15},
    )
    assert answer.status_code == 200, answer.text
    frames = _lines(answer.text)
    numbers = [f["frame"] for f in frames]
    # Real time skips frames already late (a loaded machine can fall behind even over 40 ms
    # at 4x): from the seek on, in order, none repeated, and the last frame always sent.
    assert numbers[-1] == 20 and numbers == sorted(set(numbers)), numbers
    assert set(numbers) <= set(range(15, 21)), numbers
    assert all([s["provider"] for s in f["samples"]] == ["icub/cam/right"] for f in frames)
    status = server.client.get(BASE).json()
    assert (status["recording"], status["frames"], status["complete"]) == (False, 21, True)


@pytest.mark.slow
def test_export_is_a_tar_of_a_bag_rosbags_reads(
    recorded_over_http: tuple[Any, list[Any]], tmp_path: Path
) -> None:
    server, sent = recorded_over_http
    answer = server.client.get(f"{BASE}/export")
    assert answer.status_code == 200
    with tarfile.open(fileobj=io.BytesIO(answer.content)) as tar:
        tar.extractall(tmp_path, filter="data")
    with AnyReader([tmp_path / "ep-http"]) as reader:
        skin = [
            np.asarray(reader.deserialize(raw, c.msgtype).data)
            for c, _, raw in reader.messages()
            if c.topic == "/icub/skin"
        ]
    assert [s.tobytes() for s in skin] == [s["icub/skin"].tobytes() for s in sent[:10]]


BAD: list[tuple[str, str, dict[str, Any], int, str]] = [
    (
        "post",
        "/samples",
        {"content": b"{not json", "headers": {"content-type": "application/json"}},
        422,
        "body",
    ),
    ("post", "/samples", {"json": {"ticks": []}}, 422, "ticks"),
    ("post", "/samples", {"json": {"ticks": [{"samples": {"nope": 1}}]}}, 404, "nope"),
    ("post", "/samples", {"json": {"ticks": [{"samples": {"j": [1, 2]}}]}}, 422, "samples[j]"),
    (
        "post",
        "/samples",
        {"json": {"ticks": [{"samples": {"j": [1, 2, 3]}, "time_ns": "x"}]}},
        422,
        "time_ns",
    ),
    (
        "post",
        "/samples",
        {"content": b"abc", "headers": {"content-type": "text/plain"}},
        422,
        "content-type",
    ),
    (
        "post",
        "/samples",
        {"content": b"\x10\x00\x00\x00{}", "headers": {"content-type": BATCH_MEDIA_TYPE}},
        422,
        "body",
    ),
    (
        "post",
        "/samples",
        {"json": {"ticks": [{"samples": {"cam": {"dtype": "uint8", "shape": [2], "b64": "!!"}}}]}},
        422,
        "b64",
    ),
    (
        "post",
        "/providers/cam/samples",
        {"content": b"\x00" * 10, "headers": {"x-engram-shape": "2,2,3"}},
        422,
        "shape",
    ),
    ("post", "/providers/ghost/samples", {"content": b"\x00"}, 404, "ghost"),
    ("post", "/providers", {"json": {"name": "x y", "kind": "string"}}, 422, "name"),
    ("post", "/providers", {"json": {"name": "x", "kind": "smell"}}, 422, "kind"),
    ("post", "/providers", {"json": {"name": "j", "kind": "string"}}, 422, "name"),
    ("delete", "/providers/ghost", {}, 404, "ghost"),
    ("get", "/replay", {}, 409, "still recording"),
    ("post", "", {}, 409, "recording already"),
]


@pytest.mark.slow
@pytest.mark.parametrize(("method", "path", "options", "code", "fragment"), BAD)
def test_bad_input_gets_4xx_naming_the_field(
    live_server: Any, method: str, path: str, options: dict[str, Any], code: int, fragment: str
) -> None:
    client = live_server.client
    client.post("/episodes", json={"activity": "babbling", "id": "ep-http"})
    client.post(BASE)
    client.post(
        f"{BASE}/providers", json={"name": "j", "kind": "joint_state", "names": ["a", "b", "c"]}
    )
    client.post(f"{BASE}/providers", json={"name": "cam", "kind": "image"})
    answer = getattr(client, method)(BASE + path, **options)
    assert answer.status_code == code, answer.text
    assert fragment in answer.text
    status = client.get(BASE).json()
    assert all(c["count_received"] == 0 for c in status["channels"])  # nothing recorded


@pytest.mark.slow
def test_unknown_episodes_and_channels_are_404(live_server: Any) -> None:
    client = live_server.client
    assert client.get("/episodes/nothing/streams/replay").status_code == 404
    assert client.get("/episodes/nothing/streams").status_code == 404
    assert client.post("/episodes/nothing/streams/close").status_code == 404
    answer = client.post("/episodes/bad%20id/streams")
    assert answer.status_code == 422 and answer.json()["field"] == "episode_id"
    client.post("/episodes", json={"activity": "say", "id": "e1"})
    client.post("/episodes/e1/streams")
    client.post("/episodes/e1/streams/providers", json={"name": "s", "kind": "string"})
    client.post("/episodes/e1/streams/samples", json={"ticks": [{"samples": {"s": "hi"}}]})
    client.post("/episodes/e1/streams/close")
    answer = client.get("/episodes/e1/streams/replay", params={"channels": "mic"})
    assert answer.status_code == 404 and "'mic' is not a channel" in answer.json()["detail"]


@pytest.mark.slow
def test_writes_need_the_token_when_one_is_set(start_server: Callable[..., Any]) -> None:
    server = start_server(token="s3cret")
    client = server.client
    assert client.post("/episodes/e2/streams").status_code == 401
    auth = {"authorization": "Bearer s3cret"}
    client.post("/episodes", json={"activity": "say", "id": "e2"}, headers=auth)
    assert client.post("/episodes/e2/streams", headers=auth).status_code == 201
    answer = client.post("/episodes/e2/streams/providers", json={"name": "s", "kind": "string"})
    assert answer.status_code == 401
    assert client.get("/episodes/e2/streams").status_code == 200  # reads need no token
