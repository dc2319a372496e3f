"""``EpisodeMemory``: the autobiographical memory over one store and one data directory.

It ties the graph side (episodes, annotations, cues, augmentation runs, ratings) to the stream
side (``episodes.streams``: one rosbag2 directory per episode under ``<data_dir>/streams``, and
one per augmentation run under ``<data_dir>/augmentations/<episode>``).

>>> import datetime as dt
>>> from kg import Store
>>> clock = lambda: dt.datetime(2026, 2, 26, 10, 0, tzinfo=dt.UTC)
>>> memory = EpisodeMemory(Store(), clock=clock)
>>> e = memory.begin("babbling", arguments=[ArgumentSpec("agent", "HyungJin")],
...                  begin="2026-01-26T15:30:00+00:00")
>>> _ = memory.end(e.id, end="2026-01-26T15:31:00+00:00")
>>> memory.recall(Cue("babbling", agent="HyungJin"), which="last").when
'one month ago, on January 26th'
"""

import datetime as dt
import logging
import shutil
import threading
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any
from typing import Literal as Which

from pyoxigraph import Literal

from episodes import augmentation, cues, feedback, lifecycle, transfer
from episodes.archive import StreamArchive
from episodes.augmentation import DerivedSpec
from episodes.cues import Cue
from episodes.errors import EpisodeNotFoundError, EpisodeStateError, InvalidInputError
from episodes.feedback import Ranking
from episodes.knowledge import ActivityKnowledge, activity_knowledge
from episodes.lifecycle import ArgumentSpec
from episodes.model import (
    Annotation,
    AugmentationRun,
    DerivedSample,
    Episode,
    EpisodeSummary,
    Rating,
    Recollection,
    StreamDescriptor,
)
from episodes.snapshot import MemoryState, read_memory_state
from episodes.streamlink import descriptors_from_recording, descriptors_from_stats
from episodes.streams import Recorder, RecordingRegistry, Replayer, StreamError, import_bag
from episodes.terms import check_id, episode_iri, new_id
from episodes.times import Clock, parse_time, system_clock
from kg import Store
from ontologies.vocab import EPISODES, STREAM_FILE

__all__ = ["EpisodeMemory"]

log = logging.getLogger(__name__)


class EpisodeMemory:
    """Episodes, their streams, augmentations and feedback.

    ``data_dir`` holds the stream files (none are written without it); ``clock`` gives "now"
    (time-zone aware) for default times and for phrases like "one month ago"; ``recordings``
    is the process's ``episodes.streams.RecordingRegistry`` (one is made when omitted);
    ``memory_state`` reads the scene memory's state for the episodes' snapshots (by default
    from the stored scores, see :mod:`episodes.snapshot`).
    """

    def __init__(
        self,
        store: Store,
        *,
        data_dir: Path | None = None,
        clock: Clock = system_clock,
        recordings: Any = None,
        memory_state: MemoryState = read_memory_state,
        archive: StreamArchive | None = None,
    ) -> None:
        self.store = store
        self.archive = archive
        """Where ended episodes' recordings go (object storage), if anywhere."""
        self.memory_state = memory_state
        self.data_dir = data_dir
        self.clock = clock
        self._recordings = recordings
        self._run_writers: dict[tuple[str, str], Any] = {}
        self._lock = threading.Lock()

    # Paths and the stream side ---------------------------------------------------------------

    @property
    def recordings(self) -> Any:
        """The registry of open recordings (``episodes.streams.RecordingRegistry``)."""
        if self._recordings is None:
            self._recordings = RecordingRegistry()
        return self._recordings

    def _dir(self, name: str) -> Path:
        if self.data_dir is None:
            raise EpisodeStateError("streams: this memory has no data directory for stream files")
        return self.data_dir / name

    def streams_path(self, episode_id: str) -> Path:
        """The rosbag2 directory of an episode's streams."""
        return self._dir("streams") / check_id(episode_id, "episode")

    def run_path(self, episode_id: str, run_id: str) -> Path:
        """The rosbag2 directory of an augmentation run's derived samples."""
        return (
            self._dir("augmentations") / check_id(episode_id, "episode") / check_id(run_id, "run")
        )

    def _now(self) -> dt.datetime:
        now = self.clock()
        if now.tzinfo is None:
            raise ValueError("clock: returned a naive datetime; it must be time-zone aware")
        return now

    def _time(self, value: dt.datetime | str | None, field: str) -> dt.datetime:
        return self._now() if value is None else parse_time(value, field)

    # Episodes --------------------------------------------------------------------------------

    def begin(
        self,
        activity: str,
        *,
        activity_type: str | None = None,
        arguments: Sequence[ArgumentSpec] = (),
        begin: dt.datetime | str | None = None,
        episode_id: str | None = None,
        record: bool = False,
    ) -> Episode:
        """Begin an episode (now by default); with ``record``, open its stream recording."""
        episode_id = check_id(episode_id, "id") if episode_id is not None else new_id()
        started = self._time(begin, "begin")
        path = self.streams_path(episode_id) if record else None
        if path is not None:
            # checked before opening, so that a taken id never touches that episode's streams
            if lifecycle.episode_times(self.store, episode_iri(episode_id)) is not None:
                raise EpisodeStateError(f"id: an episode {episode_id!r} already exists")
            self.recordings.open(episode_id, path)
        try:
            lifecycle.begin_episode(
                self.store,
                activity=activity,
                activity_type=activity_type,
                arguments=arguments,
                begin=started,
                episode_id=episode_id,
                memory_state=self.memory_state,
            )
        except BaseException:
            if path is not None:
                self.recordings.close(episode_id)
                shutil.rmtree(path, ignore_errors=True)
            raise
        return self.get(episode_id)

    def end(self, episode_id: str, *, end: dt.datetime | str | None = None) -> Episode:
        """End a running episode (now by default); close its recording and describe its streams."""
        ended = self._time(end, "end")
        episode = self.get(episode_id)
        if episode.end is not None:
            raise EpisodeStateError(
                f"end: episode {episode_id!r} already ended at {episode.end.isoformat()}"
            )
        if ended < episode.begin:
            raise InvalidInputError(
                "end", ended.isoformat(), f"a time not before the begin {episode.begin.isoformat()}"
            )
        streams = self._close_streams(episode_id)
        lifecycle.end_episode(
            self.store, episode_id, end=ended, streams=streams, memory_state=self.memory_state
        )
        if self.archive is not None:  # issue 19: the recording moves to object storage
            try:
                self.archive.archive(self.store, episode_id)
            except StreamError as error:
                log.warning("episode %s: recording kept local: %s", episode_id, error)
        return self.get(episode_id)

    def local_streams(self, episode_id: str) -> Path:
        """The episode's bag directory for reading: fetched from object storage if need be."""
        if self.archive is not None:
            return self.archive.local(self.store, check_id(episode_id, "episode"))
        return self.streams_path(episode_id)

    def _close_streams(self, episode_id: str) -> list[StreamDescriptor]:
        """Close the episode's recording if it is open and describe what it holds."""
        if self.data_dir is None and self._recordings is None:
            return []
        if episode_id in self.recordings:
            return descriptors_from_stats(self.recordings.close(episode_id), self._dir("streams"))
        if self.data_dir is not None and self.streams_path(episode_id).exists():
            replayer = Replayer(self.streams_path(episode_id))
            return descriptors_from_recording(replayer, self._dir("streams"))
        return []

    def import_bag(
        self,
        path: Path | str,
        activity: str,
        *,
        activity_type: str | None = None,
        arguments: Sequence[ArgumentSpec] = (),
        episode_id: str | None = None,
    ) -> Episode:
        """Import a ROS 1 bag file or ROS 2 bag directory as a finished episode.

        The samples become the episode's recording (channels mapped, times kept, see
        ``episodes.streams.import_bag``); the episode begins and ends with the bag's first and
        last message and carries an ``imported_from`` annotation. The scene memory's state at
        the time is unknown, so no snapshots are recorded. Nothing stays behind on failure.
        """

        episode_id = check_id(episode_id, "id") if episode_id is not None else new_id()
        if lifecycle.episode_times(self.store, episode_iri(episode_id)) is not None:
            raise EpisodeStateError(f"id: an episode {episode_id!r} already exists")
        dest = self.streams_path(episode_id)
        result = import_bag(path, dest=dest, episode_id=episode_id)
        try:
            start = _from_ns(result.start_ns) or self._now()
            lifecycle.begin_episode(
                self.store,
                activity=activity,
                activity_type=activity_type,
                arguments=arguments,
                begin=start,
                episode_id=episode_id,
                end=_from_ns(result.end_ns) or start,
                streams=descriptors_from_stats(result.channels, self._dir("streams")),
                snapshots=False,
            )
        except BaseException:
            shutil.rmtree(dest, ignore_errors=True)
            raise
        self.annotate(episode_id, key="imported_from", value=str(path), author="engram import")
        return self.get(episode_id)

    def get(self, episode_id: str) -> Episode:
        """Everything about one episode; raises :class:`EpisodeNotFoundError`."""
        return lifecycle.get_episode(self.store, episode_id)

    def annotate(
        self,
        episode_id: str,
        *,
        key: str,
        value: str,
        author: str | None = None,
        confidence: float | None = None,
        start: dt.datetime | str | None = None,
        end: dt.datetime | str | None = None,
    ) -> Annotation:
        """Annotate an episode, optionally over a time range inside it."""
        return lifecycle.add_annotation(
            self.store,
            episode_id,
            key=key,
            value=value,
            created=self._now(),
            author=author,
            confidence=confidence,
            start=start,
            end=end,
        )

    def link_scene(self, episode_id: str, scene: str) -> None:
        """Say that the experienced scene ``scene`` (an IRI) happened during the episode."""
        lifecycle.link_scene(self.store, episode_id, scene)

    def delete(self, episode_id: str) -> None:
        """Delete an episode everywhere: its triples, scene links, stream and derived files.

        The files are first moved aside, then the triples go in one transaction, then the files
        are removed; if the transaction fails the files are moved back.
        """
        episode = episode_iri(episode_id)
        if lifecycle.episode_times(self.store, episode) is None:
            raise EpisodeNotFoundError(episode_id)
        if self._recordings is not None and episode_id in self._recordings:
            self._recordings.close(episode_id)
        for key in [k for k in self._run_writers if k[0] == episode_id]:
            self._run_writers.pop(key).close()
        stored = self.archive.stored(self.store, episode_id) if self.archive else []
        moved: list[tuple[Path, Path]] = []
        if self.data_dir is not None:
            for path in (self.streams_path(episode_id), self._dir("augmentations") / episode_id):
                if path.exists():
                    aside = path.with_name(f".deleting-{path.name}")
                    path.rename(aside)
                    moved.append((path, aside))
        try:
            with self.store.transaction() as tx:
                lifecycle.delete_episode_triples(tx, self.store, episode_id)
        except BaseException:
            for path, aside in moved:
                aside.rename(path)
            raise
        for _, aside in moved:
            shutil.rmtree(aside, ignore_errors=True)
        if self.archive is not None and stored:
            self.archive.delete(stored)
        log.info("episode %s deleted", episode_id)

    def export_rdf(self, episode_id: str) -> bytes:
        """The episode's triples as TriG (see :mod:`episodes.transfer`)."""
        return transfer.export_episode(self.store, episode_id)

    def import_rdf(self, data: bytes) -> Episode:
        """Load an episode exported by :meth:`export_rdf` into this memory."""
        return self.get(transfer.import_episode(self.store, data))

    # Queries by cue --------------------------------------------------------------------------

    def recall(
        self,
        cue: Cue,
        *,
        which: Which["first", "last", "nth"] = "last",
        n: int = 1,
        now: dt.datetime | None = None,
    ) -> Recollection:
        """The first, last or n-th episode matching ``cue``, with when it was in words."""
        return cues.recall(self.store, cue, which=which, n=n, now=now or self._now())

    def all(self, cue: Cue, *, now: dt.datetime | None = None) -> list[Recollection]:
        """All episodes matching ``cue``, oldest first."""
        return cues.all_episodes(self.store, cue, now=now or self._now())

    def count(self, cue: Cue) -> int:
        """How many episodes match ``cue``."""
        return cues.count_episodes(self.store, cue)

    def between(
        self, start: dt.datetime | str, end: dt.datetime | str, *, now: dt.datetime | None = None
    ) -> list[Recollection]:
        """What happened between ``start`` and ``end``."""
        return cues.happened_between(self.store, start, end, now=now or self._now())

    def knowledge(self, activity: str | None = None) -> list[ActivityKnowledge]:
        """What the episodes say about each activity (or one): how often, when, with whom."""
        return activity_knowledge(self.store, activity)

    # Augmentation ----------------------------------------------------------------------------

    def start_run(
        self,
        episode_id: str,
        *,
        name: str,
        producer: str,
        parameters: Mapping[str, Any] | None = None,
    ) -> AugmentationRun:
        """Open a new, versioned run of augmentation ``name`` on an episode."""
        return augmentation.start_run(
            self.store,
            episode_id,
            name=name,
            producer=producer,
            parameters=parameters,
            started=self._now(),
        )

    def runs(self, episode_id: str) -> list[AugmentationRun]:
        return augmentation.list_runs(self.store, episode_id)

    def add_derived(
        self,
        episode_id: str,
        run_id: str,
        samples: Sequence[DerivedSpec],
        *,
        values: Sequence[Any] | None = None,
        channels: Mapping[str, Mapping[str, Any]] | None = None,
    ) -> list[DerivedSample]:
        """Record derived samples of a run, linked to their source frames.

        With ``values`` (one per sample) the data goes into the run's stream file, each sample
        at the tick time of its source frame so that originals and derivations replay side by
        side; ``channels`` declares each derived channel's kind and settings the first time
        (``{"left/edges": {"kind": "image", "encoding": "rgb8"}}``).
        """
        if values is not None and len(values) != len(samples):
            raise InvalidInputError("values", len(values), f"one value per sample ({len(samples)})")
        if values is not None:
            augmentation.check_derived(self.store, episode_id, run_id, samples)
            self._write_derived(episode_id, run_id, samples, values, channels or {})
        return augmentation.add_derived(self.store, episode_id, run_id, samples)

    def _write_derived(
        self,
        episode_id: str,
        run_id: str,
        samples: Sequence[DerivedSpec],
        values: Sequence[Any],
        channels: Mapping[str, Mapping[str, Any]],
    ) -> None:

        run = augmentation.get_run(self.store, episode_id, run_id)
        if run.ended is not None:
            raise EpisodeStateError(f"run: run {run_id!r} has ended; start a new run")
        key = (episode_id, run_id)
        with self._lock:
            writer = self._run_writers.get(key)
            if writer is None:
                source = self.local_streams(episode_id)
                times = (
                    {t.frame: t.time_ns for t in Replayer(source).ticks} if source.exists() else {}
                )
                writer = _RunWriter(
                    Recorder(self.run_path(episode_id, run_id), episode_id=episode_id), times
                )
                self._run_writers[key] = writer
                with self.store.transaction() as tx:
                    tx.insert(
                        augmentation.run_iri(episode_id, run_id),
                        STREAM_FILE,
                        Literal(
                            self.run_path(episode_id, run_id).relative_to(self._dir(".")).as_posix()
                        ),
                        EPISODES,
                    )
        writer.write(samples, values, channels)

    def end_run(self, episode_id: str, run_id: str) -> AugmentationRun:
        """Close a run (and its stream file)."""
        writer = self._run_writers.pop((episode_id, run_id), None)
        if writer is not None:
            writer.close()
        return augmentation.end_run(self.store, episode_id, run_id, ended=self._now())

    def lacking(
        self, activity: str, augmentation_name: str, *, versions: int = 1
    ) -> list[tuple[EpisodeSummary, int]]:
        """Episodes of ``activity`` with fewer than ``versions`` runs of the augmentation."""
        return augmentation.episodes_lacking(
            self.store, activity=activity, augmentation=augmentation_name, versions=versions
        )

    # Feedback --------------------------------------------------------------------------------

    def rate(
        self,
        episode_id: str,
        run_id: str,
        *,
        person: str,
        value: int,
        time: dt.datetime | str | None = None,
        sample: int | None = None,
    ) -> Rating:
        """Store a person's 1-10 rating of a run (or of one of its derived samples)."""
        return feedback.rate(
            self.store,
            episode_id,
            run_id,
            person=person,
            value=value,
            time=self._time(time, "time"),
            sample=sample,
        )

    def rank(
        self, augmentation_name: str, *, episode_id: str | None = None, alpha: float = 0.05
    ) -> Ranking:
        """Rank the rated candidates of an augmentation (quartile heuristic, Wilcoxon)."""
        return feedback.rank(self.store, augmentation_name, episode_id=episode_id, alpha=alpha)

    def close(self) -> None:
        """Close open run files (the recordings belong to whoever owns the registry)."""
        for key in list(self._run_writers):
            self._run_writers.pop(key).close()


def _from_ns(ns: int | None) -> dt.datetime | None:
    return None if ns is None else dt.datetime.fromtimestamp(ns / 1e9, dt.UTC)


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
            time_ns = self.frame_times.get(spec.frame)
            if time_ns is None or time_ns <= self.last_ns:
                time_ns = None  # no recorded source time, or out of order: the writer's own clock
            result = self.recorder.tick({spec.derived_channel: value}, time_ns=time_ns)
            self.last_ns = max(self.last_ns, int(getattr(result, "time_ns", 0) or 0))

    def close(self) -> None:
        self.recorder.close()
