"""The episode timeline: every episode with its participants, annotation ranges, stored scenes,
augmentation runs and ratings, read through :class:`episodes.EpisodeMemory`."""

import datetime as dt

from pyoxigraph import Literal, NamedNode

from api.views.models import (
    Annotation,
    EpisodeEntry,
    EpisodeList,
    RatingEntry,
    RunEntry,
    SceneEntry,
)
from api.views.scenes import scene_entries
from episodes import EpisodeMemory
from episodes.terms import episode_iri
from ontologies.vocab import EPISODIC

__all__ = ["episode_list"]

_EVER = ("0001-01-01T00:00:00+00:00", "9999-12-31T23:59:59+00:00")


def _ratings(memory: EpisodeMemory, episode_id: str) -> list[RatingEntry]:
    rows = memory.store.select("episodes_ratings", episode=episode_iri(episode_id))
    out = []
    for row in rows:
        run, person, value, time = (row.get(k) for k in ("run", "person", "value", "time"))
        if isinstance(run, NamedNode) and isinstance(value, Literal) and isinstance(time, Literal):
            out.append(
                RatingEntry(
                    run=run.value.rsplit("/", 1)[-1].rsplit("#", 1)[-1],
                    person=person.value if isinstance(person, Literal) else "",
                    value=int(value.value),
                    time=dt.datetime.fromisoformat(time.value),
                )
            )
    return out


def _entry(memory: EpisodeMemory, episode_id: str) -> EpisodeEntry:
    episode = memory.get(episode_id)
    scenes: list[SceneEntry] = scene_entries(
        memory.store, [NamedNode(s) for s in episode.scenes], EPISODIC
    )
    return EpisodeEntry(
        id=episode.id,
        activity=episode.activity,
        activity_type=episode.activity_type,
        begin=episode.begin,
        end=episode.end,
        participants=[f"{a.role}: {a.value}" for a in episode.arguments],
        annotations=[
            Annotation(key=a.key, value=a.value, start=a.start, end=a.end)
            for a in episode.annotations
        ],
        scenes=scenes,
        runs=[
            RunEntry(
                id=r.id,
                name=r.name,
                version=r.version,
                started=r.started,
                ended=r.ended,
                samples=r.samples,
            )
            for r in memory.runs(episode_id)
        ],
        ratings=_ratings(memory, episode_id),
        channels=len(episode.streams),
    )


def episode_list(memory: EpisodeMemory, *, offset: int, limit: int) -> EpisodeList:
    """Every episode, oldest first, ``limit`` of them in full from ``offset``."""
    found = memory.between(*_EVER)
    page = found[offset : offset + limit]
    return EpisodeList(
        total=len(found),
        offset=offset,
        limit=limit,
        episodes=[_entry(memory, r.episode.id) for r in page],
    )
