"""Where an episode memory keeps its stream files under its data directory.

>>> paths = DataPaths(Path("/data"))
>>> paths.streams("e1").as_posix(), paths.run("e1", "r1").as_posix()
('/data/streams/e1', '/data/augmentations/e1/r1')
"""

from dataclasses import dataclass
from pathlib import Path

from episodes.errors import EpisodeStateError
from episodes.terms import check_id

__all__ = ["DataPaths"]


@dataclass(frozen=True)
class DataPaths:
    """The data directory's layout: ``streams/<episode>`` holds an episode's rosbag2 recording,
    ``augmentations/<episode>/<run>`` a run's derived samples, ``uploads/`` scratch space.
    ``root`` ``None`` means no stream files: asking for a path raises
    :class:`EpisodeStateError`."""

    root: Path | None

    def dir(self, name: str) -> Path:
        if self.root is None:
            raise EpisodeStateError("streams: this memory has no data directory for stream files")
        return self.root / name

    def streams(self, episode_id: str) -> Path:
        """The rosbag2 directory of an episode's streams."""
        return self.dir("streams") / check_id(episode_id, "episode")

    def runs(self, episode_id: str) -> Path:
        """The directory of all the runs of an episode."""
        return self.dir("augmentations") / check_id(episode_id, "episode")

    def run(self, episode_id: str, run_id: str) -> Path:
        """The rosbag2 directory of an augmentation run's derived samples."""
        return self.runs(episode_id) / check_id(run_id, "run")
