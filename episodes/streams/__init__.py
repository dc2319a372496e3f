"""Multi-modal stream recording and replay for episodes: one rosbag2 (MCAP) file per episode.

Pure files and numpy, no RDF. The episode graph (``episodes``) stores only the descriptors
(:class:`ChannelStats`) of what is recorded here.

* :class:`RecordingRegistry`: the open recordings of the process, by episode id.
* :class:`Recorder`: typed providers, ticks, baseline filter, rate limit, background writes.
* :class:`Replayer`: frame by frame or real time, seek, channel subsets, provenance.
* :func:`export_bag`, :func:`import_bag`, :func:`recover`: bags in and out.
"""

from episodes.streams.bagio import ImportResult, export_bag, import_bag, recover
from episodes.streams.errors import (
    CorruptRecordingError,
    InvalidSampleError,
    RecordingNotFoundError,
    RecordingStateError,
    StreamError,
    UnknownProviderError,
)
from episodes.streams.ledger import ChannelStats
from episodes.streams.messages import Kind, ProviderSpec
from episodes.streams.recorder import Recorder, TickResult
from episodes.streams.registry import RecordingRegistry, bag_path, check_episode_id
from episodes.streams.replay import Frame, Replayer, Sample, TickInfo

__all__ = [
    "ChannelStats",
    "CorruptRecordingError",
    "Frame",
    "ImportResult",
    "InvalidSampleError",
    "Kind",
    "ProviderSpec",
    "Recorder",
    "RecordingNotFoundError",
    "RecordingRegistry",
    "RecordingStateError",
    "Replayer",
    "Sample",
    "StreamError",
    "TickInfo",
    "TickResult",
    "UnknownProviderError",
    "bag_path",
    "check_episode_id",
    "export_bag",
    "import_bag",
    "recover",
]
