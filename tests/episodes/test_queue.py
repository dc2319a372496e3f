"""Augmenters pick up pending work: claim, heartbeat, complete, and leases that run out
(issue 16 item 8); the example augmenter in the repository does it over HTTP."""

import base64
import json
import threading
import time

import httpx
import numpy as np
import pytest

from episodes import EpisodeMemory, InvalidInputError, NotFoundError
from episodes.example_augmenter import augment_one
from episodes.queue import AugmentationQueue
from tests.conftest import LiveServer


class FakeClock:
    def __init__(self) -> None:
        self.now = 1000.0

    def __call__(self) -> float:
        return self.now


@pytest.fixture
def babblings(memory: EpisodeMemory) -> EpisodeMemory:
    """b1 and b2 ended, b3 still running."""
    for i in (1, 2, 3):
        memory.begin("babbling", begin=f"2026-01-0{i}T10:00:00+00:00", episode_id=f"b{i}")
        if i < 3:
            memory.end(f"b{i}", end=f"2026-01-0{i}T10:10:00+00:00")
    return memory


def test_each_ended_episode_lacking_the_run_goes_to_one_worker(babblings: EpisodeMemory) -> None:
    queue = AugmentationQueue(babblings.runs, monotonic=FakeClock())
    first = queue.claim("ks", worker="w1", activity="babbling")
    second = queue.claim("ks", worker="w2", activity="babbling")
    assert first is not None and second is not None
    assert (first.episode_id, second.episode_id) == ("b1", "b2")
    assert first.run.producer == "w1" and first.run.version == 1
    assert queue.claim("ks", worker="w3", activity="babbling") is None  # b3 has not ended
    assert queue.complete(first.token).ended is not None
    with pytest.raises(NotFoundError):
        queue.complete(first.token)
    assert [e.id for e, _ in babblings.runs.lacking("babbling", "ks")] == ["b3"]


def test_a_lease_that_runs_out_discards_the_run_and_frees_the_episode(
    babblings: EpisodeMemory,
) -> None:
    clock = FakeClock()
    queue = AugmentationQueue(babblings.runs, monotonic=clock)
    lost = queue.claim("ks", worker="w1", activity="babbling", lease_s=10)
    assert lost is not None
    clock.now += 8
    queue.heartbeat(lost.token, lease_s=10)
    clock.now += 8  # 16 s after the claim, 8 after the heartbeat: still held
    kept = queue.claim("ks", worker="w2", activity="babbling")
    assert kept is not None and kept.episode_id == "b2"
    clock.now += 5  # past the renewed lease
    again = queue.claim("ks", worker="w3", activity="babbling")
    assert again is not None and again.episode_id == "b1" and again.run.version == 1
    assert [r.id for r in babblings.runs.of_episode("b1")] == [again.run.id]
    with pytest.raises(NotFoundError):
        queue.heartbeat(lost.token)


def test_a_claim_can_wait_for_work(babblings: EpisodeMemory) -> None:
    queue = AugmentationQueue(babblings.runs)
    for _ in range(2):
        assert queue.claim("ks", worker="w", activity="babbling") is not None
    threading.Timer(0.3, lambda: babblings.end("b3", end="2026-01-03T10:10:00+00:00")).start()
    started = time.monotonic()
    found = queue.claim("ks", worker="w", activity="babbling", wait_s=20)
    assert found is not None and found.episode_id == "b3"
    assert time.monotonic() - started < 20


@pytest.mark.parametrize(
    ("options", "field"),
    [
        ({"lease_s": 0}, "lease_s"),
        ({"lease_s": 1e9}, "lease_s"),
        ({"wait_s": 600}, "wait_s"),
        ({"worker": ""}, "worker"),
    ],
)
def test_bad_claims_name_the_field(babblings: EpisodeMemory, options: dict, field: str) -> None:
    arguments = {"worker": "w", "activity": "babbling", **options}
    with pytest.raises(InvalidInputError) as caught:
        babblings.runs.queue.claim("ks", **arguments)
    assert caught.value.field == field
    assert babblings.runs.of_episode("b1") == []


def test_the_example_augmenter_does_the_pending_work_over_http(live_server: LiveServer) -> None:
    client = live_server.client
    for episode in ("e1", "e2"):
        client.post("/episodes", json={"activity": "babbling", "id": episode, "record": True})
        provider = {"name": "hand", "kind": "float_array", "shape": [2]}
        client.post(f"/episodes/{episode}/streams/providers", json=provider)
        ticks = [{"samples": {"hand": [i, 2 * i]}} for i in range(1, 6)]
        client.post(f"/episodes/{episode}/streams/samples", json={"ticks": ticks})
        client.post(f"/episodes/{episode}/end", json={})
    with httpx.Client(base_url=live_server.url, timeout=60) as augmenter:
        done = [augment_one(augmenter, activity="babbling", source="hand", batch=2)]
        done.append(augment_one(augmenter, activity="babbling", source="hand"))
        assert augment_one(augmenter, activity="babbling", source="hand") is None
    assert [(r["episode_id"], r["samples"]) for r in done if r] == [("e1", 5), ("e2", 5)]
    assert all(r and r["ended"] for r in done)
    run = done[0]["id"] if done[0] else ""
    replayed = client.get(f"/episodes/e1/runs/{run}/replay").text.splitlines()
    assert len(replayed) == 5
    lacking = client.get(
        "/episodes/lacking", params={"activity": "babbling", "augmentation": "energy"}
    )
    assert lacking.json() == []
    energies = [
        float(np.frombuffer(base64.b64decode(s["value"]["b64"]))[0])
        for line in replayed
        for s in json.loads(line)["samples"]
    ]
    assert energies == [5.0 * i * i for i in range(1, 6)]
