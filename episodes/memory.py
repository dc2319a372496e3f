"""``EpisodeMemory``: the autobiographical memory over one store and one data directory.

It ties the graph side (episodes, annotations, cues, augmentation runs, ratings) to the stream
side (``episodes.streams``: one rosbag2 directory per episode under ``<data_dir>/streams``, and
one per augmentation run under ``<data_dir>/augmentations/<episode>``). The episodes' lifecycle
and the queries by cue are its own methods; the rest are parts, one idea each:
``memory.streams`` (the episodes' recordings, :mod:`episodes.stream_files`), ``memory.runs``
(augmentation runs and their queue, :mod:`episodes.runs`), ``memory.ratings`` (feedback,
:mod:`episodes.ratings`) and ``memory.imports`` (bags, :mod:`episodes.bag_imports`).

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
from collections.abc import Sequence
from pathlib import Path
from typing import Literal as Which

from episodes import arguments, cue_index, cues, lifecycle, time_index, times, transfer
from episodes.archive import StreamArchive
from episodes.bag_imports import BagImports
from episodes.cues import Cue
from episodes.errors import EpisodeNotFoundError, EpisodeStateError, InvalidInputError
from episodes.knowledge import ActivityKnowledge, activity_knowledge
from episodes.lifecycle import ArgumentSpec
from episodes.model import Annotation, Argument, Episode, Recollection
from episodes.paths import DataPaths
from episodes.ratings import Ratings
from episodes.runs import AugmentationRuns
from episodes.scene_channel import write_episode_scenes
from episodes.snapshot import MemoryState, read_memory_state
from episodes.stream_files import StreamFiles
from episodes.streams import RecordingRegistry, StreamError
from episodes.streams.mcapread import LIMIT_BYTES
from episodes.terms import ArgumentKind, check_id, episode_iri, new_id
from episodes.times import system_clock, time_or_now
from episodes.world import WorldChange, world_change
from kg import Store
from kg.clock import Clock

__all__ = ["EpisodeMemory"]

log = logging.getLogger(__name__)


class EpisodeMemory:
    """Episodes: their lifecycle, annotations, arguments and queries by cue; and its parts.

    ``data_dir`` holds the stream files (none are written without it); ``clock`` gives "now"
    (time-zone aware) for default times and for phrases like "one month ago"; ``recordings``
    is the process's ``episodes.streams.RecordingRegistry`` (one is made when omitted);
    ``memory_state`` reads the scene memory's state for the episodes' snapshots (by default
    from the stored scores, see :mod:`episodes.snapshot`); ``archive`` is where ended
    episodes' recordings go (object storage), if anywhere; ``read_limit_bytes`` bounds each
    record and decompressed chunk a replayer reads (``streams.mcapread``).
    """

    def __init__(
        self,
        store: Store,
        *,
        data_dir: Path | None = None,
        clock: Clock = system_clock,
        recordings: RecordingRegistry | None = None,
        memory_state: MemoryState = read_memory_state,
        archive: StreamArchive | None = None,
        read_limit_bytes: int = LIMIT_BYTES,
    ) -> None:
        self.store = store
        self.archive = archive
        self.memory_state = memory_state
        self.data_dir = data_dir
        self.clock = clock
        self.paths = DataPaths(data_dir)
        self.streams = StreamFiles(
            store, self.paths, archive, recordings=recordings, read_limit_bytes=read_limit_bytes
        )
        """The episodes' recordings (see :mod:`episodes.stream_files`)."""
        self.runs = AugmentationRuns(store, self.streams, clock=clock)
        """Augmentation runs, their stream files and queue (see :mod:`episodes.runs`)."""
        self.ratings = Ratings(store, clock=clock, memory_state=memory_state)
        """People's ratings of the runs, and their ranking (see :mod:`episodes.ratings`)."""
        self.imports = BagImports(store, self.paths, clock=clock)
        """Bags imported as finished episodes (see :mod:`episodes.bag_imports`)."""
        if store.remote is None or not store.remote.read_only:
            cue_index.backfill(store)  # arguments stored before the cue index existed
            time_index.backfill(store)  # episodes stored before the time index existed

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
        started = time_or_now(self.clock, begin, "begin")
        if record:
            self.streams.path(episode_id)  # raises first when there is no data directory
            # checked before opening, so that a taken id never touches that episode's streams
            if lifecycle.episode_times(self.store, episode_iri(episode_id)) is not None:
                raise EpisodeStateError(f"id: an episode {episode_id!r} already exists")
            self.streams.open(episode_id)
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
            if record:
                self.streams.abandon(episode_id)
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
        ended = time_or_now(self.clock, end, "end")
        episode = self.get(episode_id)
        if episode.end is not None:
            raise EpisodeStateError(
                f"end: episode {episode_id!r} already ended at {episode.end.isoformat()}"
            )
        if ended < episode.begin:
            raise InvalidInputError(
                "end", ended.isoformat(), f"a time not before the begin {episode.begin.isoformat()}"
            )
        streams = self.streams.finish(episode_id)
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
            created=times.now(self.clock),
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
            assertion=arguments.Assertion(
                time_or_now(self.clock, time, "time"), author, confidence
            ),
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
            assertion=arguments.Assertion(time_or_now(self.clock, time, "time"), author),
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
        self.streams.stop(episode_id)
        self.runs.files.close_episode(episode_id)
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
        return cues.recall(self.store, cue, which=which, n=n, now=now or times.now(self.clock))

    def all(self, cue: Cue, *, now: dt.datetime | None = None) -> list[Recollection]:
        """All episodes matching ``cue``, oldest first."""
        return cues.all_episodes(self.store, cue, now=now or times.now(self.clock))

    def count(self, cue: Cue) -> int:
        """How many episodes match ``cue``."""
        return cues.count_episodes(self.store, cue)

    def between(
        self, start: dt.datetime | str, end: dt.datetime | str, *, now: dt.datetime | None = None
    ) -> list[Recollection]:
        """What happened between ``start`` and ``end``."""
        return cues.happened_between(self.store, start, end, now=now or times.now(self.clock))

    def knowledge(self, activity: str | None = None) -> list[ActivityKnowledge]:
        """What the episodes say about each activity (or one): how often, when, with whom."""
        return activity_knowledge(self.store, activity)

    def close(self) -> None:
        """Close open run files (the recordings belong to whoever owns the registry)."""
        self.runs.files.close()
