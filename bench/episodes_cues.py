"""Queries by cue over a memory of many episodes: time per query, and the ratio to a point
lookup of one episode (``episodes_get``) measured in the same process.

    .venv/bin/python bench/episodes_cues.py [--episodes 10000] [--repeat 21]

Target (issue 16): every cue query under 20 ms median over 10,000 episodes. The listing of
all episodes of an activity (2,500 answers here) is printed too, with its cost per answer: its
time grows with the size of the answer, so it is not held to the cue target.
"""

import argparse
import datetime as dt
import sys
import time
from collections.abc import Callable
from pathlib import Path

from pyoxigraph import Literal, NamedNode

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from bench.timing import median_s
from episodes import ArgumentSpec, Cue, EpisodeMemory, cues, lifecycle
from episodes.terms import episode_iri
from episodes.times import to_literal
from kg import Store


def summaries_by_query(store: Store, episodes: list[NamedNode]) -> list[object]:
    """How the summaries were read before episodes/summaries.py: the grouped query, 200 a
    VALUES table."""
    rows = []
    for i in range(0, len(episodes), 200):
        rows += store.select_each("episodes_summary", "episode", episodes[i : i + 200])
    return [cues._summary(row) for row in rows]


def before_the_indexes(
    store: Store, start: dt.datetime, hours: int
) -> dict[str, Callable[[], object]]:
    """The same questions as the query shapes before the time index and episodes/summaries.py
    answered them (every begin time filtered; every episode of the activity sorted)."""
    recent = {
        "from": to_literal(start + dt.timedelta(hours=hours - 72)),
        "to": to_literal(start + dt.timedelta(hours=hours)),
    }

    def last() -> object:
        found = store.select("episodes_activity_last2", activity=Literal("babbling"))[:1]
        return [store.select("episodes_summary", episode=row["episode"]) for row in found]

    def between() -> object:
        found = store.select("episodes_between", **recent)
        return summaries_by_query(store, [row["episode"] for row in found])  # type: ignore[misc]

    def all_by_agent() -> object:
        return summaries_by_query(store, cues.matching(store, Cue("take", agent="person1")))

    return {
        "last time (activity)": last,
        "all (agent, 357 answers)": all_by_agent,
        "between (last 3 days)": between,
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--episodes", type=int, default=10_000)
    parser.add_argument("--repeat", type=int, default=21)
    args = parser.parse_args()
    now = dt.datetime(2026, 3, 1, tzinfo=dt.UTC)
    memory = EpisodeMemory(Store(), clock=lambda: now)
    start = dt.datetime(2025, 1, 1, tzinfo=dt.UTC)
    t0 = time.perf_counter()
    for k in range(args.episodes):
        # each episode lasts 30 minutes (recorded whole, as an import does); the newest one runs
        begun = start + dt.timedelta(hours=k)
        lifecycle.begin_episode(
            memory.store,
            activity=("babbling", "point", "take", "give")[k % 4],
            arguments=[
                ArgumentSpec("agent", f"person{k % 7}"),
                ArgumentSpec("object", f"o{k % 5}"),
                ArgumentSpec("recipient", f"person{(k + 3) % 7}"),
            ],
            begin=begun,
            end=begun + dt.timedelta(minutes=30) if k < args.episodes - 1 else None,
            episode_id=f"e{k}",
        )
    print(f"{args.episodes} episodes written in {time.perf_counter() - t0:.1f} s")
    store = memory.store
    baseline = median_s(
        lambda: store.select("episodes_get", episode=episode_iri("e1")), args.repeat
    )
    cases: dict[str, Callable[[], object]] = {
        "last time (activity)": lambda: memory.recall(Cue("babbling"), which="last"),
        "first time (agent, object)": lambda: memory.recall(
            Cue("babbling", agent="person3", obj="o2"), which="first"
        ),
        "n-th time (n = 100)": lambda: memory.recall(Cue("babbling"), which="nth", n=100),
        "how many times (agent)": lambda: memory.count(Cue("take", agent="person1")),
        "last time (recipient role)": lambda: memory.recall(
            Cue("point", role="recipient", participant="person2"), which="last"
        ),
        "how many (any role)": lambda: memory.count(Cue("give", participant="person4")),
        "all (agent, 357 answers)": lambda: memory.all(Cue("take", agent="person1")),
        "between (3 days)": lambda: memory.between(start, start + dt.timedelta(days=3)),
        "between (last 3 days)": lambda: memory.between(
            start + dt.timedelta(hours=args.episodes - 72),
            start + dt.timedelta(hours=args.episodes),
        ),
    }
    print(f"{'query':<28} {'ms':>8} {'x point lookup':>15}")
    print(f"{'point lookup (baseline)':<28} {baseline * 1000:8.2f} {1.0:15.1f}")
    worst = 0.0
    for name, call in cases.items():
        seconds = median_s(call, args.repeat)
        worst = max(worst, seconds)
        print(f"{name:<28} {seconds * 1000:8.2f} {seconds / baseline:15.1f}")
    answers = len(memory.all(Cue("give")))
    listing = median_s(lambda: memory.all(Cue("give")), args.repeat)
    print(
        f"{'listing: all (activity)':<28} {listing * 1000:8.2f} {listing / baseline:15.1f}"
        f"   ({answers} answers, {listing / answers * 1e6:.1f} us each)"
    )
    print("before the time index and the summaries' pattern reads (same store, same run):")
    for name, call in before_the_indexes(store, start, args.episodes).items():
        old, new = median_s(call, args.repeat), median_s(cases[name], args.repeat)
        print(f"  {name:<26} {old * 1000:8.2f} -> {new * 1000:6.2f} ms  ({old / new:.1f}x)")
    verdict = "met" if worst < 0.020 else "NOT met"
    print(f"slowest cue median {worst * 1000:.2f} ms: target < 20 ms {verdict}")
    with open("/proc/loadavg") as load:
        print(f"load average: {load.read().strip()}")


if __name__ == "__main__":
    main()
