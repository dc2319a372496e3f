"""The whole autobiographical memory through the real server on loopback: record an episode
with joints, skin and two cameras; query it by cue; replay it both ways; augment it; rate and
rank the augmentations; delete it everywhere."""

import json
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from episodes.streams import Replayer
from episodes.streams.wire import BATCH_MEDIA_TYPE, encode_batch, encode_value
from tests.conftest import LiveServer, wire_array

T0 = 1_769_441_400_000_000_000  # 2026-01-26T15:30:00Z in ns
MS = 1_000_000
NOW = "2026-02-26T10:00:00+00:00"
TAXELS = 4224
JOINTS = [f"j{i}" for i in range(53)]


def _frames(text: str) -> list[dict[str, Any]]:
    return [json.loads(line) for line in text.splitlines() if line]


@pytest.fixture
def recorded(live_server: LiveServer) -> tuple[LiveServer, list[dict[str, np.ndarray]]]:
    """Episode ep1 (HyungJin babbling with his left hand), 30 ticks of joints and skin, two
    cameras on every other tick; ended through the episode endpoint."""
    client = live_server.client
    begun = client.post(
        "/episodes",
        json={
            "activity": "babbling",
            "type": "action",
            "id": "ep1",
            "record": True,
            "begin": "2026-01-26T15:30:00+00:00",
            "arguments": [
                {"role": "agent", "value": "HyungJin"},
                {"role": "object", "value": "left hand"},
                {"role": "recipient", "value": "iCub"},
            ],
        },
    )
    assert begun.status_code == 201, begun.text
    providers = [
        {"name": "icub/joints", "kind": "joint_state", "names": JOINTS},
        {
            "name": "icub/skin",
            "kind": "float_array",
            "dtype": "float32",
            "shape": [TAXELS],
            "baseline": 0.0,
        },
        {"name": "icub/cam/left", "kind": "image", "encoding": "rgb8"},
        {"name": "icub/cam/right", "kind": "image", "encoding": "rgb8"},
    ]
    for provider in providers:
        answer = client.post("/episodes/ep1/streams/providers", json=provider)
        assert answer.status_code == 201, answer.text
    rng = np.random.default_rng(6)
    sent: list[dict[str, np.ndarray]] = []
    ticks = []
    for i in range(30):
        skin = np.zeros(TAXELS, dtype=np.float32)
        if i % 5 == 0:
            skin[rng.integers(0, TAXELS, 20)] = rng.uniform(5, 50, 20).astype(np.float32)
        samples: dict[str, np.ndarray] = {"icub/joints": rng.normal(size=53), "icub/skin": skin}
        if i % 2 == 0:
            for side in ("left", "right"):
                samples[f"icub/cam/{side}"] = rng.integers(0, 256, (24, 32, 3), dtype=np.uint8)
        ticks.append({"time_ns": T0 + i * 10 * MS, "samples": samples})
        sent.append(samples)
    answer = client.post(
        "/episodes/ep1/streams/samples",
        content=encode_batch(ticks),
        headers={"content-type": BATCH_MEDIA_TYPE},
    )
    assert answer.status_code == 200, answer.text
    ended = client.post("/episodes/ep1/end", json={"end": "2026-01-26T15:30:01+00:00"})
    assert ended.status_code == 200, ended.text
    return live_server, sent


@pytest.mark.slow
def test_record_query_replay_augment_rate_rank_delete(
    recorded: tuple[LiveServer, list[dict[str, np.ndarray]]],
) -> None:
    server, sent = recorded
    client = server.client
    data_dir = Path(server.settings.data_dir)

    # The stream descriptors are in the graph.
    episode = client.get("/episodes/ep1").json()
    streams = {s["provider"]: s for s in episode["streams"]}
    assert {p: (s["count"], s["dropped"]) for p, s in streams.items()} == {
        "icub/joints": (30, 0),
        "icub/skin": (30, 0),
        "icub/cam/left": (15, 0),
        "icub/cam/right": (15, 0),
    }
    assert streams["icub/joints"]["first_time"] == "2026-01-26T15:30:00+00:00"
    assert (data_dir / "streams" / streams["icub/skin"]["file"]).is_file()

    # Query by cue.
    recalled = client.get(
        "/episodes/recall",
        params={"activity": "babbling", "agent": "HyungJin", "object": "left hand", "now": NOW},
    ).json()
    assert recalled["episode"]["id"] == "ep1"
    assert recalled["when"] == "one month ago, on January 26th"
    assert recalled["episode"]["participants"] == ["HyungJin", "iCub", "left hand"]

    # Replay frame by frame over HTTP: bit-exact, skin restored from its baseline.
    frames = _frames(client.get("/episodes/ep1/streams/replay").text)
    assert len(frames) == 30
    for frame, samples in zip(frames, sent, strict=True):
        got = {s["provider"]: s for s in frame["samples"]}
        assert set(got) == set(samples)
        for name, value in samples.items():
            replayed = got[name]["value"]
            replayed = replayed["position"] if name == "icub/joints" else replayed
            assert wire_array(replayed).tobytes() == value.tobytes(), (frame["frame"], name)
            assert got[name]["episode"] == "ep1"
    # ... in real time, a subset of channels, and in Python.
    realtime = _frames(
        client.get(
            "/episodes/ep1/streams/replay",
            params={"mode": "realtime", "speed": 10, "channels": ["icub/cam/left"]},
        ).text
    )
    assert realtime and all(
        [s["provider"] for s in f["samples"]] == ["icub/cam/left"] for f in realtime
    )
    last_left = next(s for s in reversed(sent) if "icub/cam/left" in s)["icub/cam/left"]
    assert wire_array(realtime[-1]["samples"][0]["value"]).tobytes() == last_left.tobytes()
    python_frames = list(Replayer(data_dir / "streams" / "ep1").frames(["icub/skin"]))
    assert [f.samples["icub/skin"].value.tobytes() for f in python_frames] == [
        s["icub/skin"].tobytes() for s in sent
    ]

    # A-posteriori augmentation: two versioned runs of edge images derived from left frames.
    lacking = client.get(
        "/episodes/lacking", params={"activity": "babbling", "augmentation": "edges"}
    ).json()
    assert [e["episode"]["id"] for e in lacking] == ["ep1"]
    left_frames = [f for f in frames if any(s["provider"] == "icub/cam/left" for s in f["samples"])]
    runs = []
    for threshold in (50, 90):
        run = client.post(
            "/episodes/ep1/runs",
            json={"name": "edges", "producer": "canny", "parameters": {"threshold": threshold}},
        )
        assert run.status_code == 201, run.text
        run_id = run.json()["id"]
        derived = []
        for f in left_frames[:5]:
            image = wire_array(
                next(s for s in f["samples"] if s["provider"] == "icub/cam/left")["value"]
            )
            edges = (image.mean(axis=2) > threshold).astype(np.uint8) * 255
            derived.append(
                {
                    "frame": f["frame"],
                    "source_channel": "/icub/cam/left",
                    "derived_channel": "icub/cam/left/edges",
                    "value": encode_value(edges),
                }
            )
        posted = client.post(
            f"/episodes/ep1/runs/{run_id}/samples",
            json={
                "samples": derived,
                "channels": {"icub/cam/left/edges": {"kind": "image", "encoding": "mono8"}},
            },
        )
        assert posted.status_code == 201, posted.text
        assert client.post(f"/episodes/ep1/runs/{run_id}/end").status_code == 200
        runs.append(run_id)
    listed = client.get("/episodes/ep1/runs").json()
    assert [(r["version"], r["samples"], r["parameters"]) for r in listed] == [
        (1, 5, {"threshold": 50}),
        (2, 5, {"threshold": 90}),
    ]
    # Derived frames sit at their source frames' times: originals and derivations side by side.
    derived_replay = list(Replayer(data_dir / "augmentations" / "ep1" / runs[0]).frames())
    assert [f.time_ns for f in derived_replay] == [f["time_ns"] for f in left_frames[:5]]
    assert (
        client.get(
            "/episodes/lacking", params={"activity": "babbling", "augmentation": "edges"}
        ).json()
        == []
    )

    # Feedback from five people and the paper's ranking.
    scores = {runs[0]: [6, 6, 8, 8, 9], runs[1]: [3, 4, 4, 5, 4]}
    for run_id, values in scores.items():
        for person, value in zip("ABCDE", values, strict=True):
            answer = client.post(
                f"/episodes/ep1/runs/{run_id}/ratings", json={"person": person, "value": value}
            )
            assert answer.status_code == 201, answer.text
    ranking = client.get("/augmentations/edges/ranking", params={"episode": "ep1"}).json()
    assert ranking["leader"] == f"ep1/{runs[0]}"
    assert ranking["best"] == [f"ep1/{runs[0]}"]
    assert [c["good"] for c in ranking["candidates"]] == [True, False]

    # Delete everywhere: triples, stream files, derived files.
    assert _episode_triples(client) > 100
    assert client.delete("/episodes/ep1").status_code == 204
    assert client.get("/episodes/ep1").status_code == 404
    assert not (data_dir / "streams" / "ep1").exists()
    assert not (data_dir / "augmentations" / "ep1").exists()
    assert client.get("/episodes/ep1/streams/replay").status_code == 404
    assert client.get("/episodes/count", params={"activity": "babbling"}).json() == {"count": 0}
    assert _episode_triples(client) == 0


def _episode_triples(client: Any) -> int:
    """Triples in the episodes graph, asked through the SPARQL endpoint."""
    query = (
        "SELECT (COUNT(*) AS ?n) WHERE "
        "{ GRAPH <https://w3id.org/engram/graph/episodes> { ?s ?p ?o } }"
    )
    answer = client.get(
        "/sparql", params={"query": query}, headers={"Accept": "application/sparql-results+json"}
    )
    return int(answer.json()["results"]["bindings"][0]["n"]["value"])
