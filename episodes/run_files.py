"""The stream files of augmentation runs: derived samples written at their source frames'
times, read back, replayed beside the originals and exported as their own topics per version.

One rosbag2 directory per run, ``<data_dir>/augmentations/<episode>/<run>`` (see
:class:`episodes.paths.DataPaths`); a run's writer stays open until the run ends.
"""

import threading
from collections.abc import Iterator, Mapping, Sequence
from pathlib import Path
from typing import Any

from pyoxigraph import Literal

from episodes import augmentation
from episodes.augmentation import DerivedSpec
from episodes.errors import EpisodeStateError, InvalidInputError, NotFoundError
from episodes.stream_files import StreamFiles
from episodes.streams import Recorder, Replayer, export_bag
from episodes.streams.merge import derived_frames, export_merged, merged_frames, run_prefix
from episodes.streams.replay import Frame
from kg import Store
from ontologies.vocab import EPISODES, STREAM_FILE

__all__ = ["RunFiles"]

FrameChannels = dict[int, frozenset[str]]
"""Frame number -> the providers and channels with a sample at that frame."""


class RunFiles:
    """The runs' stream files of one memory, beside the episodes' recordings ``streams``."""

    def __init__(self, store: Store, streams: StreamFiles) -> None:
        self.store = store
        self.streams = streams
        self.paths = streams.paths
        self.read_limit_bytes = streams.read_limit_bytes
        """Bounds each record and decompressed chunk read (:mod:`episodes.streams.mcapread`)."""
        self._writers: dict[tuple[str, str], _RunWriter] = {}
        self._frames: dict[str, tuple[tuple[object, ...], FrameChannels]] = {}
        self._lock = threading.Lock()

    def _replayer(self, path: Path) -> Replayer:
        return Replayer(path, limit_bytes=self.read_limit_bytes)

    def recorded_frames(self, episode_id: str) -> FrameChannels:
        """Frame number -> the providers and channels with a sample at that frame, as the
        episode's stream file holds them (empty without a recording). Cached per file state."""
        if self.paths.root is None:
            return {}
        path = self.paths.streams(episode_id)
        if not path.exists():
            return {}
        key = tuple(_file_state(f) for f in sorted(path.glob("*.mcap")))
        cached = self._frames.get(episode_id)
        if cached is not None and cached[0] == key:
            return cached[1]
        frames = {
            tick.frame: frozenset(
                name for provider in tick.providers for name in (provider, "/" + provider)
            )
            for tick in self._replayer(path).ticks
        }
        self._frames[episode_id] = (key, frames)
        return frames

    def write(
        self,
        episode_id: str,
        run_id: str,
        samples: Sequence[DerivedSpec],
        values: Sequence[Any],
        channels: Mapping[str, Mapping[str, Any]],
    ) -> None:
        """Write derived samples (already checked) into the run's stream file; the first write
        opens it and records its path with the run."""
        run = augmentation.get_run(self.store, episode_id, run_id)
        if run.ended is not None:
            raise EpisodeStateError(f"run: run {run_id!r} has ended; start a new run")
        key = (episode_id, run_id)
        with self._lock:
            writer = self._writers.get(key)
            if writer is None:
                source = self.streams.local(episode_id)
                times = (
                    {t.frame: t.time_ns for t in self._replayer(source).ticks}
                    if source.exists()
                    else {}
                )
                path = self.paths.run(episode_id, run_id)
                writer = _RunWriter(Recorder(path, episode_id=episode_id), times)
                self._writers[key] = writer
                with self.store.transaction() as tx:
                    tx.insert(
                        augmentation.run_iri(episode_id, run_id),
                        STREAM_FILE,
                        Literal(path.relative_to(self.paths.dir(".")).as_posix()),
                        EPISODES,
                    )
        writer.write(samples, values, channels)

    def stored(self, episode_id: str, run_id: str) -> bool:
        """Whether the run has a stream file."""
        return self.paths.root is not None and self.paths.run(episode_id, run_id).exists()

    def replayer(self, episode_id: str, run_id: str) -> tuple[str, Replayer]:
        """The run's name prefix and a replayer of its stream file (flushed if still open).
        Raises :class:`NotFoundError` when the run has no derived data stored."""
        run = augmentation.get_run(self.store, episode_id, run_id)
        writer = self._writers.get((episode_id, run_id))
        if writer is not None:
            writer.recorder.flush()
        path = self.paths.run(episode_id, run_id)
        if not path.exists():
            raise NotFoundError(
                f"run: run {run_id!r} of episode {episode_id!r} has no derived data stored "
                "(post samples with values)"
            )
        return run_prefix(run.name, run.version), self._replayer(path)

    def channels(self, episode_id: str, run_id: str) -> list[str]:
        """The derived channels a run's stream file holds (none without one)."""
        if not self.stored(episode_id, run_id):
            return []
        return sorted(self.replayer(episode_id, run_id)[1].providers)

    def replay(
        self,
        episode_id: str,
        run_id: str,
        *,
        merge: bool = False,
        channels: Sequence[str] | None = None,
    ) -> Iterator[Frame]:
        """A run's derived samples frame by frame, numbered by their source frames; with
        ``merge``, the source frames (``channels`` of them) with the derived samples beside
        the originals, named ``augmentations/<name>/v<version>/<channel>``."""
        prefix, run = self.replayer(episode_id, run_id)
        source = self._replayer(self.paths.streams(episode_id))
        if merge:
            return merged_frames(source, [(prefix, run)], channels)
        return derived_frames(source, run, channels)

    def export(self, episode_id: str, dest: Path, *, with_runs: bool = False) -> None:
        """The episode's streams as a standalone rosbag2 directory ``dest``; with
        ``with_runs``, every run's derived channels too, each its own topic per version."""
        source = self.paths.streams(episode_id)
        runs = []
        if with_runs:
            for run in augmentation.list_runs(self.store, episode_id):
                if self.stored(episode_id, run.id):
                    prefix, _ = self.replayer(episode_id, run.id)  # flushes a run still open
                    runs.append((prefix, self.paths.run(episode_id, run.id)))
        if runs:
            export_merged(source, runs, dest, limit_bytes=self.read_limit_bytes)
        else:
            export_bag(source, dest, limit_bytes=self.read_limit_bytes)

    def close_run(self, episode_id: str, run_id: str) -> None:
        """Close the run's stream file if it is open."""
        writer = self._writers.pop((episode_id, run_id), None)
        if writer is not None:
            writer.close()

    def close_episode(self, episode_id: str) -> None:
        """Close the stream files of all the episode's runs."""
        for key in [k for k in self._writers if k[0] == episode_id]:
            self._writers.pop(key).close()

    def close(self) -> None:
        for key in list(self._writers):
            self._writers.pop(key).close()


def _file_state(path: Path) -> tuple[str, int, int]:
    state = path.stat()
    return path.name, state.st_mtime_ns, state.st_size


class _RunWriter:
    """The stream file of one augmentation run: derived samples at their source frames' times."""

    def __init__(self, recorder: Any, frame_times: dict[int, int]) -> None:
        self.recorder = recorder
        self.frame_times = frame_times
        self.last_ns = 0

    def write(
        self,
        samples: Sequence[DerivedSpec],
        values: Sequence[Any],
        channels: Mapping[str, Mapping[str, Any]],
    ) -> None:
        for name, settings in channels.items():
            options = dict(settings)
            kind = options.pop("kind", None)
            self.recorder.add_provider(name, kind, **options)
        for i, (spec, value) in enumerate(zip(samples, values, strict=True)):
            if spec.derived_channel not in self.recorder.providers:
                raise InvalidInputError(
                    f"samples[{i}].derived_channel",
                    spec.derived_channel,
                    "a derived channel declared in 'channels' (kind and settings)",
                )
            source_ns = time_ns = self.frame_times.get(spec.frame)
            if time_ns is None or time_ns <= self.last_ns:
                time_ns = None  # no recorded source time, or out of order: the writer's own clock
            # the stamp is the source frame's tick time, whatever the tick time: replay and
            # export match derived samples to their source frames by it
            stamps = {spec.derived_channel: source_ns} if source_ns is not None else None
            result = self.recorder.tick(
                {spec.derived_channel: value}, time_ns=time_ns, stamps_ns=stamps
            )
            self.last_ns = max(self.last_ns, int(getattr(result, "time_ns", 0) or 0))

    def close(self) -> None:
        self.recorder.close()
