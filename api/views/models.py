"""The JSON the web views read, as pydantic models (so it is part of the OpenAPI)."""

import datetime as dt
from typing import Literal

from pydantic import BaseModel, Field

from kg.primitive import Primitive

__all__ = [
    "Annotation",
    "ChannelInfo",
    "ChannelList",
    "ClassDetail",
    "ClassList",
    "ClassNode",
    "EpisodeEntry",
    "EpisodeList",
    "FrameList",
    "PlotData",
    "RatingEntry",
    "Relation",
    "Restriction",
    "RunEntry",
    "SceneDetail",
    "SceneEntry",
    "SceneList",
    "ScorePoint",
]

Level = Literal["HIGH", "LOW", "WEAK"]


class ClassNode(BaseModel):
    """One learned scene class as the memory graph draws it."""

    name: str = Field(description="Local name, e.g. Scene-3.")
    iri: str
    complexity: int = Field(description="d: the sum of the signature's counts.")
    score: float = Field(description="Normalised score now (the best class is 1).")
    level: Level
    pinned: bool
    forgotten: bool = Field(description="In the trash.")
    items: int = Field(description="Experienced scenes stored as this class.")
    store_count: int
    retrieve_count: int
    parents: list[str] = Field(description="Names of the direct superclasses.")
    relations: list[str] | None = Field(
        None,
        description='The signature in words, one entry per key: "sphere isAboveOf plane" '
        "(left out of a list asked for with relations=false).",
    )


class ClassList(BaseModel):
    """A page of the memory graph's classes, simplest first."""

    total: int = Field(description="Classes matching, before offset and limit.")
    offset: int
    limit: int
    classes: list[ClassNode]


class Restriction(BaseModel):
    """One restriction ``≥ n property.Type`` of a class definition."""

    property: str
    type: str
    n: int


class ScorePoint(BaseModel):
    """A class's normalised score and level at one time."""

    time: dt.datetime
    score: float
    level: Level | None


class SceneEntry(BaseModel):
    """A stored (experienced) scene in a list."""

    name: str
    iri: str
    cls: str | None = Field(description="Name of the class it was stored as.")
    created: dt.datetime | None
    episode: str | None = Field(description="Id of the episode it happened in.")
    forgotten: bool = False


class ClassDetail(BaseModel):
    """Everything the memory graph shows about one class."""

    node: ClassNode
    words: str = Field(description='"a sphere above a plane, and the plane below the sphere"')
    restrictions: list[Restriction]
    children: list[str]
    raw_score: float | None
    stored_level: str | None
    consecutive_weak: int | None
    created: dt.datetime | None
    last_accessed: dt.datetime | None
    history: list[ScorePoint] = Field(description="Score and level over time, oldest first.")
    scenes: list[SceneEntry] = Field(description="Its stored scenes, newest first (limited).")


class Relation(BaseModel):
    """A spatial relation the encoder fired between two primitives of a scene."""

    subject: str
    relation: str
    object: str


class SceneDetail(BaseModel):
    """A stored scene with its primitives and relations."""

    scene: SceneEntry
    primitives: list[Primitive] = Field(
        description="Its primitives (metres; x right, y behind, z up; colour RGB in [0, 1])."
    )
    relations: list[Relation]


class SceneList(BaseModel):
    """Stored scenes, newest first."""

    total: int
    offset: int
    limit: int
    scenes: list[SceneEntry]


class Annotation(BaseModel):
    """An annotation of an episode, over a time range when it has one."""

    key: str
    value: str
    start: dt.datetime | None
    end: dt.datetime | None


class RunEntry(BaseModel):
    """An augmentation run of an episode."""

    id: str
    name: str
    version: int
    started: dt.datetime | None
    ended: dt.datetime | None
    samples: int


class RatingEntry(BaseModel):
    """A person's rating of an augmentation run (or of a sample it derived)."""

    run: str
    person: str
    value: int
    time: dt.datetime


class EpisodeEntry(BaseModel):
    """An episode on the timeline."""

    id: str
    activity: str
    activity_type: str | None
    begin: dt.datetime
    end: dt.datetime | None
    participants: list[str]
    annotations: list[Annotation]
    scenes: list[SceneEntry]
    runs: list[RunEntry]
    ratings: list[RatingEntry]
    channels: int = Field(description="Recorded stream channels.")


class EpisodeList(BaseModel):
    """Episodes, oldest first."""

    total: int
    offset: int
    limit: int
    episodes: list[EpisodeEntry]


class ChannelInfo(BaseModel):
    """One recorded channel of an episode's stream file."""

    name: str
    kind: str
    samples: int
    first_s: float | None = Field(description="Seconds after the recording's first tick.")
    last_s: float | None
    coverage: list[int] = Field(description="Samples in each of equal time bins over the file.")
    numeric: bool = Field(description="Can be plotted.")
    image: bool


class ChannelList(BaseModel):
    """The channels of an episode's recording."""

    episode: str
    start_ns: int | None
    end_ns: int | None
    frames: int
    channels: list[ChannelInfo]


class PlotData(BaseModel):
    """A numeric channel decimated for a plot: per bucket its minimum and its maximum."""

    channel: str
    series: list[str]
    samples: int = Field(description="Samples in the channel before decimation.")
    t: list[float] = Field(description="Seconds after the recording's first tick.")
    values: list[list[float | None]] = Field(
        description="One list per series, aligned with t (null where a sample lacks it)."
    )


class FrameList(BaseModel):
    """The frames holding a channel's samples (for a scrubber)."""

    channel: str
    total: int
    frames: list[int]
    time_ns: list[int]
