"""The autobiographical memory: episodes, annotations, stream recording and replay.

Episodes, annotations, stream descriptors, augmentation runs and ratings are RDF in the
``episodes`` named graph (PROV-O plus Engram's terms); the samples themselves are rosbag2
(MCAP) files written by :mod:`episodes.streams`. :class:`EpisodeMemory` ties both together.
"""

from episodes.augmentation import DerivedSpec
from episodes.cues import Cue
from episodes.errors import (
    EpisodeError,
    EpisodeNotFoundError,
    EpisodeStateError,
    InvalidInputError,
    NotFoundError,
)
from episodes.feedback import CandidateStats, Comparison, Ranking
from episodes.knowledge import ActivityKnowledge, Participation
from episodes.lifecycle import ArgumentSpec
from episodes.memory import EpisodeMemory
from episodes.model import (
    Annotation,
    Argument,
    AugmentationRun,
    ClassEntry,
    DerivedSample,
    Episode,
    EpisodeSummary,
    ImportReport,
    MemorySnapshot,
    Rating,
    Recollection,
    SkippedTopic,
    StreamDescriptor,
    to_jsonable,
)
from episodes.times import say_when

__all__ = [
    "ActivityKnowledge",
    "Annotation",
    "Argument",
    "ArgumentSpec",
    "AugmentationRun",
    "CandidateStats",
    "ClassEntry",
    "Comparison",
    "Cue",
    "DerivedSample",
    "DerivedSpec",
    "Episode",
    "EpisodeError",
    "EpisodeMemory",
    "EpisodeNotFoundError",
    "EpisodeStateError",
    "EpisodeSummary",
    "ImportReport",
    "InvalidInputError",
    "MemorySnapshot",
    "NotFoundError",
    "Participation",
    "Ranking",
    "Rating",
    "Recollection",
    "SkippedTopic",
    "StreamDescriptor",
    "say_when",
    "to_jsonable",
]
