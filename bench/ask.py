"""Asking the memory: speech understood, recognition speed, and text question latency at scale.

1. **Speech.** Every question of :data:`api.ask.samples.SPOKEN` (each form of the grammar) is
   spoken by espeak-ng (US English voice, at ``--speeds`` words per minute), heard by the
   pocketsphinx recogniser constrained by the grammar, and answered on the lived week of
   :mod:`api.ask.samples`. A question counts as understood and answered correctly when what
   was heard means what was said (same form, same slots ignoring case, same relation triples:
   "the ball" is "a ball") and the answer is of that form. Target: at least 90 %.
2. **Real-time factor** of recognition on one core (the process is pinned to one CPU):
   decoding time / audio duration; below 1 is faster than real time (the baseline, 1.0).
3. **Text latency**: a memory of ``--episodes`` episodes and ``--classes`` learned classes
   (built in bulk: episodes without the per-episode snapshot of the scene memory, classes with
   ``SceneMemory.learn_classes``), then every text form asked ``--repeat`` times; the median
   per form and overall (target < 50 ms), and the ratio to one point lookup of an episode
   (``episodes_get``) measured in the same run.

Run from the repository root::

    .venv/bin/python bench/ask.py                       # 10,000 episodes and classes
    .venv/bin/python bench/ask.py --quick               # small, to exercise the script
    .venv/bin/python bench/ask.py --no-speech           # text latency only
"""

import argparse
import datetime as dt
import os
import random
import statistics
import sys
import time
from pathlib import Path

from pyoxigraph import NamedNode, Quad

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

from api.ask import Asker, parse
from api.ask.grammar import Parsed, parse_thing
from api.ask.samples import SPOKEN, START, live_a_week
from api.ask.speech import Recogniser, synthesise
from episodes import ArgumentSpec, EpisodeMemory, MemorySnapshot
from episodes.terms import episode_iri
from episodes.times import to_literal
from kg import Store
from kg.clock import SimulatedClock
from kg.primitive import KINDS, Primitive
from ontologies.vocab import EPISODES, PROV_NS
from reasoners.memory import SceneMemory

STARTED, ENDED = NamedNode(PROV_NS + "startedAtTime"), NamedNode(PROV_NS + "endedAtTime")
ACTIVITIES = ("motor babbling", "pointing", "waving", "giving", "taking", "stacking")
PEOPLE = ("Anna", "Peter", "HyungJin", "Maria", "Tobias", "Lena", "Omar")


def meaning(parsed: Parsed | None) -> object:
    if parsed is None:
        return None
    slots: dict[str, object] = {k: v.lower() for k, v in parsed.slots.items()}
    if "thing" in slots:
        slots["thing"] = parse_thing(parsed.slots["thing"])
    return parsed.form, slots


def speech(speeds: list[int]) -> None:
    asker = Asker(*live_a_week(Store(), SimulatedClock(START)))
    recogniser = Recogniser()
    right = total = 0
    audio_s = decode_s = 0.0
    misses: list[str] = []
    for wpm in speeds:
        for question in SPOKEN:
            heard, answer = asker.ask_audio(synthesise(question, words_per_minute=wpm), recogniser)
            expected = parse(question)
            ok = (
                heard.text is not None
                and meaning(parse(heard.text)) == meaning(expected)
                and answer.understood
                and expected is not None
                and answer.form == expected.form
            )
            right += ok
            total += 1
            audio_s += heard.audio_s
            decode_s += heard.decode_s
            if not ok:
                misses.append(f"  {wpm} wpm: {question!r} heard as {heard.text!r}")
    print(
        f"speech: {right}/{total} questions understood and answered correctly "
        f"= {100 * right / total:.1f} % (target >= 90 %), voices: espeak-ng en-us at {speeds}"
    )
    print("\n".join(misses) or "  (no misses)")
    print(
        f"recognition real-time factor on one core: {decode_s / audio_s:.3f} "
        f"({decode_s:.1f} s decoding for {audio_s:.1f} s of audio; real time = 1.0)"
    )


def random_scene(rng: random.Random, count: int) -> list[Primitive]:
    scene = []
    for k in range(count):
        kind = rng.choice(KINDS)
        centre = (rng.uniform(0, 1), rng.uniform(0, 1), rng.uniform(0, 0.5))
        if kind == "Sphere":
            scene.append(Primitive(f"o{k}", kind, centre=centre, radius=0.04))
        elif kind == "Plane":
            scene.append(Primitive(f"o{k}", kind, centre=centre, axis=(0, 0, 1)))
        else:
            height = 0.1 if kind != "Plane" else None
            scene.append(
                Primitive(f"o{k}", kind, centre=centre, axis=(0, 0, 1), radius=0.03, height=height)
            )
    return scene


def write_episodes(store: Store, count: int, now: dt.datetime, rng: random.Random) -> None:
    """``count`` finished episodes, one an hour up to ``now``, in bulk: one template episode per
    (activity, agent, partner) is written through ``EpisodeMemory`` in a scratch store, and its
    triples are copied with the episode's IRI and times replaced, 1,000 episodes a transaction
    (through the API an episode costs two transactions and a snapshot, ~20 ms)."""
    scratch = EpisodeMemory(Store(), clock=lambda: now, memory_state=lambda _: MemorySnapshot(0, 0))
    templates = []
    for j, (activity, agent, partner) in enumerate(
        (a, p, q) for a in ACTIVITIES for p in PEOPLE for q in PEOPLE if p != q
    ):
        arguments = [ArgumentSpec("agent", agent), ArgumentSpec("partner", partner)]
        scratch.begin(activity, arguments=arguments, begin=now, episode_id=f"t{j}")
        scratch.end(f"t{j}", end=now)
        templates.append(episode_iri(f"t{j}").value)
    own: dict[str, list[Quad]] = {t: [] for t in templates}
    shared: list[Quad] = []
    for quad in scratch.store.quads(None, None, None, EPISODES):
        subject = quad.subject.value
        owner = subject.split("/episode/", 1)[-1].split("/", 1)[0]
        key = episode_iri(owner).value if "/episode/" in subject else None
        (own.get(key, shared) if key else shared).append(quad)
    first = now - dt.timedelta(hours=count)
    for chunk in range(0, count, 1000):
        with store.transaction() as tx:
            if chunk == 0:
                for quad in shared:
                    tx.insert(quad.subject, quad.predicate, quad.object, EPISODES)
            for k in range(chunk, min(chunk + 1000, count)):
                template = rng.choice(templates)
                target = episode_iri(f"e{k}").value
                begin = first + dt.timedelta(hours=k)
                times = {
                    STARTED: to_literal(begin),
                    ENDED: to_literal(begin + dt.timedelta(minutes=20)),
                }
                for quad in own[template]:
                    subject = NamedNode(quad.subject.value.replace(template, target))
                    obj = quad.object
                    if isinstance(obj, NamedNode) and obj.value.startswith(template):
                        obj = NamedNode(obj.value.replace(template, target))
                    if quad.subject.value == template and quad.predicate in times:
                        obj = times[quad.predicate]
                    tx.insert(subject, quad.predicate, obj, EPISODES)


def build(episodes: int, classes: int, seed: int) -> tuple[Asker, float]:
    rng = random.Random(seed)
    now = dt.datetime(2026, 3, 4, 10, 0, tzinfo=dt.UTC)
    clock = lambda: now  # noqa: E731
    store = Store()
    started = time.perf_counter()
    scenes = SceneMemory(store, clock=clock)
    memory = EpisodeMemory(store, clock=clock)
    write_episodes(store, episodes, now, rng)
    encoder = scenes.encoder
    batch = []
    while len(batch) < classes:
        batch.append(encoder.signature(random_scene(rng, rng.randint(2, 5))))
        if len(batch) == classes:
            batch = list(dict.fromkeys(batch))  # duplicates are learned once
    for start in range(0, len(batch), 1000):
        scenes.learn_classes(batch[start : start + 1000])
    for _ in range(3):
        scenes.store_scene(random_scene(rng, 3))
    return Asker(scenes, memory), time.perf_counter() - started


TEXT = (
    "when did Anna last show you motor babbling",
    "when was the first time HyungJin did pointing",
    "how many times did Peter do waving",
    "what happened yesterday afternoon",
    "who was there when Maria last did stacking",
    "what do you know about a ball on a table",
    "have you seen a cone behind a sphere",
    "what do you remember best",
    "what did you forget this week",
    "why did you forget Scene-4",
    "why is Scene-200 a kind of Scene-2",
    "why did you not recognise the last scene",
    "why did you learn Scene-300",
    "how well do you remember Scene-1",
    "explain Scene-500",
    "how did the score of Scene-1 change",
    "what did you know today",
)


def latency(episodes: int, classes: int, repeat: int, seed: int) -> None:
    asker, build_s = build(episodes, classes, seed)
    live = len(asker.scenes.reads.classes())
    print(f"\nmemory: {episodes} episodes, {live} classes, built in {build_s:.1f} s")
    store = asker.store
    point = []
    for _ in range(repeat * 10):
        began = time.perf_counter()
        store.select("episodes_get", episode=episode_iri("e1"))
        point.append(time.perf_counter() - began)
    baseline = statistics.median(point)
    for text in TEXT:  # first asks read the names once
        assert asker.ask(text).understood, text
    everything: list[float] = []
    print(f"{'question':<48} {'median ms':>10} {'x lookup':>9}")
    print(f"{'point lookup of one episode (baseline)':<48} {baseline * 1000:10.2f} {1.0:9.1f}")
    for text in TEXT:
        samples = []
        for _ in range(repeat):
            began = time.perf_counter()
            asker.ask(text)
            samples.append(time.perf_counter() - began)
        everything += samples
        median = statistics.median(samples)
        print(f"{text:<48} {median * 1000:10.2f} {median / baseline:9.1f}")
    median = statistics.median(everything)
    print(f"{'all forms':<48} {median * 1000:10.2f} {median / baseline:9.1f}   (target < 50 ms)")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--episodes", type=int, default=10_000)
    parser.add_argument("--classes", type=int, default=10_000)
    parser.add_argument("--repeat", type=int, default=20)
    parser.add_argument("--speeds", type=int, nargs="+", default=[145, 160, 175])
    parser.add_argument("--seed", type=int, default=7)
    parser.add_argument("--quick", action="store_true", help="200 episodes and classes")
    parser.add_argument("--no-speech", action="store_true", help="text latency only")
    args = parser.parse_args()
    if args.quick:
        args.episodes = args.classes = 200
        args.repeat = 3
        args.speeds = [160]
    if hasattr(os, "sched_setaffinity"):
        os.sched_setaffinity(0, {min(os.sched_getaffinity(0))})  # one core
    print(f"python {sys.version.split()[0]}, one core: CPU {min(os.sched_getaffinity(0))}")
    if not args.no_speech:
        speech(args.speeds)
    latency(args.episodes, args.classes, args.repeat, args.seed)


if __name__ == "__main__":
    main()
