"""Augmented streams read back: replayed alone or beside the originals, exported as their own
topics per version, and the versions of one run side by side (issue 16 item 3)."""

import io
import json
import tarfile
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from rosbags.highlevel import AnyReader

from episodes.streams.wire import encode_value
from tests.conftest import LiveServer, wire_array

T0 = 1_769_441_400_000_000_000
MS = 1_000_000


def _lines(text: str) -> list[dict[str, Any]]:
    return [json.loads(line) for line in text.splitlines() if line]


@pytest.fixture
def augmented(live_server: LiveServer) -> tuple[LiveServer, list[str]]:
    """Episode ep1: 6 frames of "arm" (3 joints), "hand" at frames 2, 4, 6; two runs of
    "pose" derived from the hand at frames 2 and 4 (v1 posts x+1, v2 x+2)."""
    client = live_server.client
    client.post("/episodes", json={"activity": "babbling", "id": "ep1", "record": True})
    for provider in (
        {"name": "arm", "kind": "float_array", "shape": [3]},
        {"name": "hand", "kind": "float_array", "shape": [2]},
    ):
        assert client.post("/episodes/ep1/streams/providers", json=provider).status_code == 201
    ticks = []
    for i in range(1, 7):
        samples: dict[str, Any] = {"arm": [i, i, i]}
        if i % 2 == 0:
            samples["hand"] = [i, -i]
        ticks.append({"time_ns": T0 + i * 10 * MS, "samples": samples})
    assert client.post("/episodes/ep1/streams/samples", json={"ticks": ticks}).status_code == 200
    assert client.post("/episodes/ep1/end", json={}).status_code == 200
    runs = []
    for shift in (1, 2):
        run = client.post("/episodes/ep1/runs", json={"name": "pose", "producer": "p"}).json()
        samples = [
            {
                "frame": frame,
                "source_channel": "hand",
                "derived_channel": "pose",
                "value": encode_value(np.array([frame + shift, 0.0])),
            }
            for frame in (2, 4)
        ]
        posted = client.post(
            f"/episodes/ep1/runs/{run['id']}/samples",
            json={"samples": samples, "channels": {"pose": {"kind": "float_array"}}},
        )
        assert posted.status_code == 201, posted.text
        runs.append(run["id"])
    client.post(f"/episodes/ep1/runs/{runs[0]}/end")  # the second stays open
    return live_server, runs


def _value(sample: dict[str, Any]) -> list[float]:
    values: list[float] = wire_array(sample["value"]).tolist()
    return values


def test_a_run_replays_alone_at_its_source_frames(augmented: tuple[LiveServer, list[str]]) -> None:
    server, runs = augmented
    for run, shift in zip(runs, (1, 2), strict=True):
        answer = server.client.get(f"/episodes/ep1/runs/{run}/replay")
        assert answer.status_code == 200, answer.text
        frames = _lines(answer.text)
        assert [f["frame"] for f in frames] == [2, 4]
        assert [f["time_ns"] for f in frames] == [T0 + 20 * MS, T0 + 40 * MS]
        assert [_value(f["samples"][0]) for f in frames] == [[2 + shift, 0.0], [4 + shift, 0.0]]


def test_a_run_replays_merged_beside_the_originals(augmented: tuple[LiveServer, list[str]]) -> None:
    server, runs = augmented
    answer = server.client.get(
        f"/episodes/ep1/runs/{runs[1]}/replay", params={"merge": True, "channels": ["hand"]}
    )
    frames = _lines(answer.text)
    assert [f["frame"] for f in frames] == [2, 4, 6]
    named = [sorted(s["provider"] for s in f["samples"]) for f in frames]
    assert named == [
        ["augmentations/pose/v2/pose", "hand"],
        ["augmentations/pose/v2/pose", "hand"],
        ["hand"],
    ]
    pose = next(s for s in frames[1]["samples"] if s["provider"].endswith("/pose"))
    assert pose["frame"] == 4 and _value(pose) == [6.0, 0.0]


def test_export_holds_each_version_as_its_own_topic(
    augmented: tuple[LiveServer, list[str]], tmp_path: Path
) -> None:
    server, _ = augmented
    answer = server.client.get("/episodes/ep1/streams/export", params={"with_runs": True})
    assert answer.status_code == 200, answer.text
    with tarfile.open(fileobj=io.BytesIO(answer.content)) as tar:
        tar.extractall(tmp_path, filter="data")
    with AnyReader([tmp_path / "ep1"]) as reader:
        counts = {c.topic: c.msgcount for c in reader.connections}
        times = {
            c.topic: [t for _, t, _ in reader.messages(connections=[c])] for c in reader.connections
        }
    assert counts["/augmentations/pose/v1/pose"] == 2 == counts["/augmentations/pose/v2/pose"]
    assert counts["/hand"] == 3 and counts["/arm"] == 6
    assert times["/augmentations/pose/v1/pose"] == times["/hand"][:2]


def test_versions_of_a_run_side_by_side(augmented: tuple[LiveServer, list[str]]) -> None:
    server, runs = augmented
    client = server.client
    for person, values in zip("ABCDE", ([8, 5], [7, 5], [9, 6], [8, 4], [7, 5]), strict=True):
        for run, value in zip(runs, values, strict=True):
            client.post(
                f"/episodes/ep1/runs/{run}/ratings", json={"person": person, "value": value}
            )
    answer = client.get("/augmentations/pose/versions", params={"episode": "ep1"})
    assert answer.status_code == 200, answer.text
    side = answer.json()
    assert [(v["run"]["version"], v["channels"], v["best"]) for v in side] == [
        (1, ["pose"], True),
        (2, ["pose"], False),
    ]
    assert side[0]["ratings"]["median"] == 8.0 and side[1]["ratings"]["n"] == 5


def test_replay_of_a_run_without_data_is_404(live_server: LiveServer) -> None:
    client = live_server.client
    client.post("/episodes", json={"activity": "babbling", "id": "e"})
    run = client.post("/episodes/e/runs", json={"name": "pose", "producer": "p"}).json()["id"]
    answer = client.get(f"/episodes/e/runs/{run}/replay")
    assert answer.status_code == 404 and "no derived data" in answer.json()["detail"]
