"""The Episodes view's read: ``GET /views/episodes?limit=200&newest=true`` (the page the view
asks for) and the largest page (500) over 10,000 episodes, against a point lookup of one
episode (``episodes_get``) in the same run, and against how a page of 500 was read before
(every episode from the year 1 to 9999 through the time index's day buckets, then each
episode's details one query at a time).

    PYTHONPATH=. .venv/bin/python bench/episode_timeline.py [--episodes 10000] [--repeat 5]

Target (issue 32): the view's read under 300 ms at 10,000 episodes.
"""

import argparse
import datetime as dt
import gc
import sys
import tempfile
import time
from pathlib import Path

from fastapi.testclient import TestClient

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from api.config import Settings
from api.main import create_app
from api.views import timeline
from bench.timing import median_s
from episodes import ArgumentSpec, EpisodeMemory, lifecycle
from episodes.terms import episode_iri
from kg import Store

START = dt.datetime(2025, 1, 1, tzinfo=dt.UTC)
VIEW_PAGE = "/views/episodes?limit=200&newest=true"
"""What the Episodes page asks for (api/web/episodes.js)."""


def build(memory: EpisodeMemory, count: int) -> None:
    """``count`` half-hour episodes an hour apart; every tenth annotated with a rated run."""
    for k in range(count):
        begun = START + dt.timedelta(hours=k)
        lifecycle.begin_episode(
            memory.store,
            activity=("babbling", "point", "take", "give")[k % 4],
            arguments=[
                ArgumentSpec("agent", f"person{k % 7}"),
                ArgumentSpec("object", f"o{k % 5}"),
            ],
            begin=begun,
            end=begun + dt.timedelta(minutes=30),
            episode_id=f"e{k}",
            snapshots=False,
        )
        if k % 10 == 0:
            memory.annotate(f"e{k}", key="phase", value="reach", start=begun, end=begun)
            run = memory.runs.start(f"e{k}", name="detector", producer="bench")
            memory.runs.end(f"e{k}", run.id)
            memory.ratings.rate(f"e{k}", run.id, person="Ana", value=7)


def before(memory: EpisodeMemory, limit: int) -> object:
    """The page as it was read before: the whole time range, then one episode at a time."""
    found = memory.between("0001-01-01T00:00:00+00:00", "9999-12-31T23:59:59+00:00")
    for recollection in found[:limit]:
        episode_id = recollection.episode.id
        memory.get(episode_id)
        memory.runs.of_episode(episode_id)
        memory.store.select("episodes_ratings", episode=episode_iri(episode_id))
    return found


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--episodes", type=int, default=10_000)
    parser.add_argument("--repeat", type=int, default=5)
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        data_dir = Path(tmp)
        now = START + dt.timedelta(hours=args.episodes + 1)
        memory = EpisodeMemory(Store(data_dir / "store"), data_dir=data_dir, clock=lambda: now)
        began = time.perf_counter()
        build(memory, args.episodes)
        print(f"{args.episodes} episodes written in {time.perf_counter() - began:.1f} s")
        memory.store.flush()
        del memory
        gc.collect()  # the server opens the directory next
        run(data_dir, args.episodes, args.repeat)


def run(data_dir: Path, episodes: int, repeat: int) -> None:
    app = create_app(Settings(data_dir=data_dir))
    with TestClient(app, base_url="http://127.0.0.1") as client:
        memory = client.app.state.services.episodes  # type: ignore[attr-defined]
        assert client.get("/views/episodes?limit=1").json()["total"] == episodes
        cases = {
            "point lookup (baseline)": lambda: memory.store.select(
                "episodes_get", episode=episode_iri("e1")
            ),
            "timeline read, 500": lambda: timeline.episode_list(memory, offset=0, limit=500),
            "GET /views/episodes?limit=500": lambda: client.get("/views/episodes?limit=500"),
            "GET the view's page (newest 200)": lambda: client.get(VIEW_PAGE),
        }
        figures = {name: median_s(call, repeat) for name, call in cases.items()}
        figures["before: read, 500 (once)"] = median_s(lambda: before(memory, 500), 1)
        cpu = median_s(
            lambda: timeline.episode_list(memory, offset=0, limit=500),
            repeat,
            clock=time.thread_time,
        )
        print(f"timeline read, 500: {cpu * 1000:.0f} ms of CPU (median of {repeat})")
    baseline = figures["point lookup (baseline)"]
    print(f"{'read':<32} {'ms':>9} {'x point lookup':>15}")
    for name, seconds in figures.items():
        print(f"{name:<32} {seconds * 1000:9.1f} {seconds / baseline:15.1f}")
    page = figures["GET the view's page (newest 200)"]
    before_s, now_s = figures["before: read, 500 (once)"], figures["timeline read, 500"]
    print(f"before / now: {before_s / now_s:.1f}x")
    verdict = "met" if page < 0.300 else "NOT met"
    print(f"GET {VIEW_PAGE}: {page * 1000:.0f} ms, target < 300 ms {verdict}")
    with open("/proc/loadavg") as load:
        print(f"load average: {load.read().strip()}")


if __name__ == "__main__":
    main()
