"""What the autobiographical memory returns: plain, immutable records.

>>> import datetime as dt
>>> to_jsonable(ClassEntry(cls="https://x/C", score=0.5, rank=1))
{'cls': 'https://x/C', 'score': 0.5, 'rank': 1}
"""

import dataclasses
import datetime as dt
from dataclasses import dataclass, field
from typing import Any

from episodes.terms import ArgumentKind

__all__ = [
    "Annotation",
    "Argument",
    "AugmentationRun",
    "ClassEntry",
    "DerivedSample",
    "Episode",
    "EpisodeSummary",
    "ImportReport",
    "MemorySnapshot",
    "Rating",
    "Recollection",
    "SkippedTopic",
    "StreamDescriptor",
    "to_jsonable",
]


@dataclass(frozen=True)
class Argument:
    """A role-labelled argument: who or what took part in the episode, and how; for one
    given after the fact, who said so (``author``), when (``asserted``) and how sure."""

    role: str
    value: str
    kind: ArgumentKind = "entity"
    iri: str = ""
    id: str = ""
    author: str | None = None
    asserted: dt.datetime | None = None
    confidence: float | None = None


@dataclass(frozen=True)
class ClassEntry:
    """One of the best scene classes of a memory snapshot."""

    cls: str
    score: float
    rank: int


@dataclass(frozen=True)
class MemorySnapshot:
    """The scene memory's state at one moment."""

    learned_classes: int
    episodic_items: int
    best_classes: tuple[ClassEntry, ...] = ()


@dataclass(frozen=True)
class Annotation:
    """Something said about an episode after the fact, optionally over a time range inside it."""

    id: str
    key: str
    value: str
    created: dt.datetime
    author: str | None = None
    confidence: float | None = None
    start: dt.datetime | None = None
    end: dt.datetime | None = None


@dataclass(frozen=True)
class StreamDescriptor:
    """One recorded channel of an episode, as the RDF graph describes it."""

    provider: str
    channel: str
    message_type: str
    count: int
    dropped: int | None
    """Samples dropped while recording; ``None`` when unknown (descriptor read from the file)."""
    file: str
    first_time: dt.datetime | None = None
    last_time: dt.datetime | None = None


@dataclass(frozen=True)
class EpisodeSummary:
    """An episode as a query by cue returns it."""

    id: str
    activity: str
    activity_type: str | None
    begin: dt.datetime
    end: dt.datetime | None
    participants: tuple[str, ...] = ()


@dataclass(frozen=True)
class Recollection:
    """An episode found by a cue, with when it was in words ("one month ago, on January 26th")."""

    episode: EpisodeSummary
    when: str
    rank: int | None = None
    said: str = ""
    """The answer in words, roles included: "The last time HyungJin was the recipient of
    pointing was one month ago, on January 26th." """


@dataclass(frozen=True)
class Episode:
    """Everything the memory holds about one episode."""

    id: str
    iri: str
    activity: str
    activity_type: str | None
    begin: dt.datetime
    end: dt.datetime | None
    arguments: tuple[Argument, ...] = ()
    state_at_begin: MemorySnapshot | None = None
    state_at_end: MemorySnapshot | None = None
    annotations: tuple[Annotation, ...] = ()
    streams: tuple[StreamDescriptor, ...] = ()
    scenes: tuple[str, ...] = ()


@dataclass(frozen=True)
class SkippedTopic:
    """A topic of an imported bag that was not imported: its message type has no channel kind."""

    topic: str
    message_type: str
    count: int


@dataclass(frozen=True)
class ImportReport:
    """What a bag import made: the episode, and the topics it skipped (with type and count)."""

    episode: Episode
    skipped: tuple[SkippedTopic, ...] = ()


@dataclass(frozen=True)
class AugmentationRun:
    """One versioned a-posteriori processing of an episode."""

    id: str
    episode_id: str
    name: str
    version: int
    producer: str
    parameters: dict[str, Any] = field(default_factory=dict)
    started: dt.datetime | None = None
    ended: dt.datetime | None = None
    samples: int = 0


@dataclass(frozen=True)
class DerivedSample:
    """A piece of derived data, linked to the recorded frame it was computed from."""

    id: str
    run_id: str
    frame: int
    source_channel: str
    derived_channel: str


@dataclass(frozen=True)
class Rating:
    """A person's 1-10 score of an augmentation run (or derived sample)."""

    id: str
    item: str
    person: str
    value: int
    time: dt.datetime
    question: str | None = None
    session: str | None = None
    """The feedback episode it was given in (see ``episodes.sessions``), if any."""


def to_jsonable(value: Any) -> Any:
    """Records, tuples and datetimes as JSON-ready dicts, lists and ISO 8601 strings."""
    if dataclasses.is_dataclass(value) and not isinstance(value, type):
        return {f.name: to_jsonable(getattr(value, f.name)) for f in dataclasses.fields(value)}
    if isinstance(value, dt.datetime):
        return value.isoformat()
    if isinstance(value, list | tuple):
        return [to_jsonable(v) for v in value]
    if isinstance(value, dict):
        return {str(k): to_jsonable(v) for k, v in value.items()}
    return value
