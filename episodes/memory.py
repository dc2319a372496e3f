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
from collections.abc import Iterator, Mapping, Sequence
from pathlib import Path
from typing import Any
from typing import Literal as Which

from episodes import (
    arguments,
    augmentation,
    bag_import,
    cue_index,
    cues,
    feedback,
    lifecycle,
    sessions,
    time_index,
    transfer,
)
from episodes.archive import StreamArchive
from episodes.augmentation import DerivedSpec
from episodes.bag_import import BagEpisode
from episodes.bag_limits import DEFAULT_LIMIT_BYTES
from episodes.cues import Cue
from episodes.errors import (
    EpisodeNotFoundError,
    EpisodeStateError,
    InvalidInputError,
)
from episodes.feedback import Ranking
from episodes.knowledge import ActivityKnowledge, activity_knowledge
from episodes.lifecycle import ArgumentSpec
from episodes.model import (
    Annotation,
    Argument,
    AugmentationRun,
    DerivedSample,
    Episode,
    EpisodeSummary,
    ImportReport,
    Rating,
    Recollection,
    StreamDescriptor,
)
from episodes.paths import DataPaths
from episodes.queue import AugmentationQueue
from episodes.run_files import RunFiles
from episodes.scene_channel import write_episode_scenes
from episodes.snapshot import MemoryState, read_memory_state
from episodes.streamlink import descriptors_from_recording, descriptors_from_stats
from episodes.streams import (
    RecordingRegistry,
    Replayer,
    StreamError,
)
from episodes.streams.mcapread import LIMIT_BYTES
from episodes.streams.replay import Frame
from episodes.terms import ArgumentKind, check_id, episode_iri, new_id
from episodes.times import Clock, parse_time, system_clock
from episodes.world import WorldChange, world_change
from kg import Store
from ontologies.vocab import EPISODES

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
        read_limit_bytes: int = LIMIT_BYTES,
    ) -> None:
        self.store = store
        self.archive = archive
        """Where ended episodes' recordings go (object storage), if anywhere."""
        self.memory_state = memory_state
        self.data_dir = data_dir
        self.clock = clock
        self._recordings = recordings
        self.paths = DataPaths(data_dir)
        self.read_limit_bytes = read_limit_bytes
        """Bounds each record and decompressed chunk a replayer reads (``streams.mcapread``)."""
        self.run_files = RunFiles(store, self.paths, archive, read_limit_bytes=read_limit_bytes)
        """The augmentation runs' stream files (see :mod:`episodes.run_files`)."""
        self._queue: AugmentationQueue | None = None
        if store.remote is None or not store.remote.read_only:
            cue_index.backfill(store)  # arguments stored before the cue index existed
            time_index.backfill(store)  # episodes stored before the time index existed

    # Paths and the stream side ---------------------------------------------------------------

    @property
    def recordings(self) -> Any:
        """The registry of open recordings (``episodes.streams.RecordingRegistry``)."""
        if self._recordings is None:
            self._recordings = RecordingRegistry()
        return self._recordings

    def streams_path(self, episode_id: str) -> Path:
        """The rosbag2 directory of an episode's streams."""
        return self.paths.streams(episode_id)

    def run_path(self, episode_id: str, run_id: str) -> Path:
        """The rosbag2 directory of an augmentation run's derived samples."""
        return self.paths.run(episode_id, run_id)

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

    def check_recordable(self, episode_id: str) -> None:
        """Raise unless ``episode_id`` is a running episode whose streams may be recorded.

        Raises :class:`EpisodeNotFoundError` (a recording needs its episode) and
        :class:`EpisodeStateError` when the episode has ended.
        """
        _, _, ended = lifecycle.require_episode(self.store, check_id(episode_id, "episode_id"))
        if ended is not None:
            raise EpisodeStateError(
                f"episode_id: episode {episode_id!r} ended at {ended.isoformat()}; "
                "streams are recorded while an episode runs"
            )

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
        if self.data_dir is not None:  # its scenes, for Foxglove (episodes/scene_channel.py)
            write_episode_scenes(self.store, self.data_dir, episode_id)
        if self.archive is not None:  # the recording moves to object storage
            try:
                self.archive.archive(self.store, episode_id)
            except StreamError as error:
                log.warning("episode %s: recording kept local: %s", episode_id, error)
        return self.get(episode_id)

    def local_streams(self, episode_id: str) -> Path:
        """The episode's bag directory for reading: fetched from object storage if need be."""
        return self.run_files.source(episode_id)

    def replayer(self, episode_id: str) -> Replayer:
        """A replayer of the episode's recording; one in object storage is read by ranges."""
        if self.archive is not None:
            return self.archive.replayer(self.store, check_id(episode_id, "episode"))
        return Replayer(self.streams_path(episode_id), limit_bytes=self.read_limit_bytes)

    def _close_streams(self, episode_id: str) -> list[StreamDescriptor]:
        """Close the episode's recording if it is open and describe what it holds."""
        if self.data_dir is None and self._recordings is None:
            return []
        if episode_id in self.recordings:
            return descriptors_from_stats(
                self.recordings.close(episode_id), self.paths.dir("streams")
            )
        if self.data_dir is not None and self.streams_path(episode_id).exists():
            replayer = Replayer(self.streams_path(episode_id), limit_bytes=self.read_limit_bytes)
            return descriptors_from_recording(replayer, self.paths.dir("streams"))
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
        last message and carries an ``imported_from`` annotation (and one ``skipped_topic``
        annotation per topic of a type that cannot be imported). The scene memory's state at
        the time is unknown, so no snapshots are recorded. Nothing stays behind on failure.
        :meth:`import_bag_report` also returns what was skipped.
        """
        return self.import_bag_report(
            path, activity, activity_type=activity_type, arguments=arguments, episode_id=episode_id
        ).episode

    def import_bag_report(
        self,
        path: Path | str,
        activity: str,
        *,
        activity_type: str | None = None,
        arguments: Sequence[ArgumentSpec] = (),
        episode_id: str | None = None,
        name: str | None = None,
        max_decompressed_bytes: int = DEFAULT_LIMIT_BYTES,
    ) -> ImportReport:
        """:meth:`import_bag`, answering the episode and the topics skipped (type and count).
        ``name`` is how messages and the ``imported_from`` annotation call the bag (default:
        ``path``); a compressed piece of the bag may expand to ``max_decompressed_bytes``.
        Raises :class:`~episodes.bag_limits.DamagedBagError` if the bag cannot be read."""
        what = BagEpisode(activity, activity_type, arguments, episode_id)
        return bag_import.import_report(
            self.store,
            self.paths,
            path,
            what,
            now=self._now(),
            name=name,
            max_decompressed_bytes=max_decompressed_bytes,
        )

    def import_source(self, path: str) -> Path:
        """The bag at ``path`` inside the data directory, for an HTTP client (see
        :func:`episodes.bag_import.import_source`)."""
        return bag_import.import_source(self.paths, path)

    @property
    def uploads_dir(self) -> Path:
        """Where uploaded files wait to be imported (inside the data directory)."""
        return self.paths.dir("uploads")

    def import_upload(
        self,
        upload: Path,
        activity: str,
        *,
        activity_type: str | None = None,
        arguments: Sequence[ArgumentSpec] = (),
        episode_id: str | None = None,
        max_decompressed_bytes: int = DEFAULT_LIMIT_BYTES,
        max_unpacked_bytes: int = 4 * 1024**3,
    ) -> ImportReport:
        """Import a bag received as the file ``upload``: a ROS 1 ``.bag`` file, or a tar of a
        ROS 2 bag directory (see :func:`episodes.bag_import.import_upload` for the limits).
        Raises :class:`InvalidInputError` (field ``body``) for anything else, and
        :class:`~episodes.bag_limits.DamagedBagError` for a bag that cannot be read."""
        what = BagEpisode(activity, activity_type, arguments, episode_id)
        return bag_import.import_upload(
            self.store,
            self.paths,
            upload,
            what,
            now=self._now(),
            max_decompressed_bytes=max_decompressed_bytes,
            max_unpacked_bytes=max_unpacked_bytes,
        )

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

    def add_argument(
        self,
        episode_id: str,
        *,
        role: str,
        value: str,
        kind: ArgumentKind | None = None,
        author: str | None = None,
        confidence: float | None = None,
        time: dt.datetime | str | None = None,
        replace: bool = False,
        replaces: str | None = None,
    ) -> Argument:
        """Add an argument after the fact (``agent = Martina`` by face recognition, 0.92);
        with ``replace``, it replaces the arguments in that role (or only ``replaces``).

        The assertion keeps its author, time (now by default) and confidence as PROV; cues
        see it at once. See :mod:`episodes.arguments`.
        """
        return arguments.add_argument(
            self.store,
            episode_id,
            role=role,
            value=value,
            kind=kind,
            assertion=arguments.Assertion(self._time(time, "time"), author, confidence),
            replace=replace,
            replaces=replaces,
        )

    def remove_argument(
        self,
        episode_id: str,
        *,
        role: str,
        value: str | None = None,
        author: str | None = None,
        time: dt.datetime | str | None = None,
    ) -> list[Argument]:
        """Retract the arguments in ``role`` (only ``value``'s when given); they stay in the
        graph, marked invalidated by ``author`` at ``time``, and cues no longer see them."""
        return arguments.remove_argument(
            self.store,
            episode_id,
            role=role,
            value=value,
            assertion=arguments.Assertion(self._time(time, "time"), author),
        )

    def world(self, episode_id: str) -> WorldChange:
        """What was on the table and who was there at the episode's begin and end, and what
        changed (see :mod:`episodes.world`); raises :class:`EpisodeNotFoundError`."""
        lifecycle.require_episode(self.store, episode_id)
        return world_change(self.store, episode_id)

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
        self.run_files.close_episode(episode_id)
        stored = self.archive.stored(self.store, episode_id) if self.archive else []
        moved: list[tuple[Path, Path]] = []
        if self.data_dir is not None:
            for path in (self.paths.streams(episode_id), self.paths.runs(episode_id)):
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
        episode_id = transfer.import_episode(self.store, data)
        cue_index.backfill(self.store)  # an export made before the cue index existed
        time_index.backfill(self.store)
        episode = self.get(episode_id)
        # the export may carry its old first/last pointers, or none: recompute them
        time_index.refresh_activity(self.store, episode.activity)
        return episode

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
        recorded = self.run_files.recorded_frames(episode_id)
        if values is not None:
            augmentation.check_derived(self.store, episode_id, run_id, samples, recorded)
            self.run_files.write(episode_id, run_id, samples, values, channels or {})
        return augmentation.add_derived(self.store, episode_id, run_id, samples, recorded)

    def recorded_frames(self, episode_id: str) -> dict[int, frozenset[str]]:
        """Frame number -> the providers and channels with a sample at that frame, as the
        episode's stream file holds them (empty without a recording)."""
        return self.run_files.recorded_frames(episode_id)

    def replay_run(
        self,
        episode_id: str,
        run_id: str,
        *,
        merge: bool = False,
        channels: Sequence[str] | None = None,
    ) -> Iterator[Frame]:
        """Replay a run's derived samples, frame by frame, numbered by their source frames;
        with ``merge``, the source frames (``channels`` of them) with the derived samples
        beside the originals, named ``augmentations/<name>/v<version>/<channel>``."""
        return self.run_files.replay(episode_id, run_id, merge=merge, channels=channels)

    def export_streams(self, episode_id: str, dest: Path, *, with_runs: bool = False) -> None:
        """Write the episode's streams as a standalone rosbag2 directory ``dest``; with
        ``with_runs``, every run's derived channels too, each its own topic per version."""
        self.run_files.export(episode_id, dest, with_runs=with_runs)

    def versions(self, augmentation_name: str, episode_id: str) -> list[dict[str, Any]]:
        """The runs of one augmentation on one episode side by side, for a rating view: each
        version with its parameters, derived samples and channels, rating summary, and
        whether it is among the best (quartile rule, Wilcoxon)."""
        ranking = self.rank(augmentation_name, episode_id=episode_id)
        stats = {c.item: c for c in ranking.candidates}
        out = []
        for run in augmentation.list_runs(self.store, episode_id):
            if run.name != augmentation_name:
                continue
            item = f"{episode_id}/{run.id}"
            channels = self.run_files.channels(episode_id, run.id)
            rated = stats.get(item)
            out.append(
                {
                    "run": run,
                    "item": item,
                    "channels": channels,
                    "ratings": rated,
                    "best": item in ranking.best,
                    "leader": item == ranking.leader,
                }
            )
        return out

    @property
    def queue(self) -> AugmentationQueue:
        """The pending augmentation work served to augmenter processes (claims and leases)."""
        if self._queue is None:
            self._queue = AugmentationQueue(self)
        return self._queue

    def discard_run(self, episode_id: str, run_id: str) -> None:
        """Delete an unfinished run everywhere (its triples and derived file), e.g. when the
        lease of the worker that claimed it runs out. Raises :class:`NotFoundError`."""
        run = augmentation.get_run(self.store, episode_id, run_id)
        if run.ended is not None:
            raise EpisodeStateError(f"run: run {run_id!r} has ended; it is kept")
        self.run_files.close_run(episode_id, run_id)
        with self.store.transaction() as tx:
            for row in self.store.select(
                "episodes_owned_nodes", episode=augmentation.run_iri(episode_id, run_id)
            ):
                tx.delete_matching(row["node"], graph=EPISODES)  # type: ignore[arg-type]
        if self.data_dir is not None:
            shutil.rmtree(self.run_path(episode_id, run_id), ignore_errors=True)
        log.info("run %s of episode %s discarded", run_id, episode_id)

    def end_run(self, episode_id: str, run_id: str) -> AugmentationRun:
        """Close a run (and its stream file)."""
        self.run_files.close_run(episode_id, run_id)
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
        question: str | None = None,
        replace: bool = False,
        session: str | None = None,
    ) -> Rating:
        """Store a person's 1-10 rating of a run (or of one of its derived samples), as the
        answer to ``question``; a second answer needs ``replace`` (see ``feedback.rate``).
        With ``session``, the rating is given in that running feedback episode, whose agent
        ``person`` must be (see :meth:`begin_feedback`)."""
        given_in = (
            sessions.check_session(self.store, check_id(session, "session"), person)
            if session is not None
            else None
        )
        return feedback.rate(
            self.store,
            episode_id,
            run_id,
            person=person,
            value=value,
            time=self._time(time, "time"),
            sample=sample,
            question=question,
            replace=replace,
            session=given_in,
        )

    def begin_feedback(
        self,
        person: str,
        *,
        rated: Sequence[str] = (),
        begin: dt.datetime | str | None = None,
        episode_id: str | None = None,
    ) -> Episode:
        """Begin a rating session as a feedback episode: ``person`` (its agent) rates the data
        of the episodes ``rated``; ratings given with ``session=<its id>`` belong to it, and
        :meth:`end` ends it. See :mod:`episodes.sessions`."""
        session_id = sessions.begin_session(
            self.store,
            person=person,
            rated=rated,
            begin=self._time(begin, "begin"),
            episode_id=check_id(episode_id, "id") if episode_id is not None else None,
            memory_state=self.memory_state,
        )
        return self.get(session_id)

    def session_ratings(self, session_id: str) -> list[Rating]:
        """The ratings given in a feedback episode, in the order given."""
        return sessions.session_ratings(self.store, check_id(session_id, "session"))

    def rank(
        self,
        augmentation_name: str,
        *,
        episode_id: str | None = None,
        alpha: float = 0.05,
        question: str | None = None,
    ) -> Ranking:
        """Rank the rated candidates of an augmentation by the answers to ``question``
        (quartile heuristic, Wilcoxon)."""
        return feedback.rank(
            self.store, augmentation_name, episode_id=episode_id, alpha=alpha, question=question
        )

    def close(self) -> None:
        """Close open run files (the recordings belong to whoever owns the registry)."""
        self.run_files.close()
