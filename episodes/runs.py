"""An episode memory's augmentation runs: versioned runs of a derivation over an episode, their
derived samples (in the graph, and with values in each run's stream file), and the queue that
serves the work to augmenter processes.

The graph side is :mod:`episodes.augmentation`, the files :mod:`episodes.run_files`, the queue
:mod:`episodes.queue`.
"""

import logging
import shutil
from collections.abc import Mapping, Sequence
from typing import Any

from episodes import augmentation, feedback
from episodes.augmentation import DerivedSpec
from episodes.errors import EpisodeStateError, InvalidInputError
from episodes.model import AugmentationRun, DerivedSample, EpisodeSummary
from episodes.queue import AugmentationQueue
from episodes.run_files import RunFiles
from episodes.stream_files import StreamFiles
from episodes.times import now
from kg import Store
from kg.clock import Clock
from ontologies.vocab import EPISODES

__all__ = ["AugmentationRuns"]

log = logging.getLogger(__name__)


class AugmentationRuns:
    """The augmentation runs of one memory; ``clock`` gives the runs' start and end times."""

    def __init__(self, store: Store, streams: StreamFiles, *, clock: Clock) -> None:
        self.store = store
        self.clock = clock
        self.files = RunFiles(store, streams)
        """The runs' stream files: written, replayed beside the originals, exported."""
        self._queue: AugmentationQueue | None = None

    def start(
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
            started=now(self.clock),
        )

    def of_episode(self, episode_id: str) -> list[AugmentationRun]:
        """The runs of an episode, every augmentation's."""
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
        recorded = self.files.recorded_frames(episode_id)
        if values is not None:
            augmentation.check_derived(self.store, episode_id, run_id, samples, recorded)
            self.files.write(episode_id, run_id, samples, values, channels or {})
        return augmentation.add_derived(self.store, episode_id, run_id, samples, recorded)

    def end(self, episode_id: str, run_id: str) -> AugmentationRun:
        """Close a run (and its stream file)."""
        self.files.close_run(episode_id, run_id)
        return augmentation.end_run(self.store, episode_id, run_id, ended=now(self.clock))

    def discard(self, episode_id: str, run_id: str) -> None:
        """Delete an unfinished run everywhere (its triples and derived file), e.g. when the
        lease of the worker that claimed it runs out. Raises :class:`NotFoundError`, and
        :class:`EpisodeStateError` for a run that has ended."""
        run = augmentation.get_run(self.store, episode_id, run_id)
        if run.ended is not None:
            raise EpisodeStateError(f"run: run {run_id!r} has ended; it is kept")
        self.files.close_run(episode_id, run_id)
        with self.store.transaction() as tx:
            for row in self.store.select(
                "episodes_owned_nodes", episode=augmentation.run_iri(episode_id, run_id)
            ):
                tx.delete_matching(row["node"], graph=EPISODES)  # type: ignore[arg-type]
        if self.files.paths.root is not None:
            shutil.rmtree(self.files.paths.run(episode_id, run_id), ignore_errors=True)
        log.info("run %s of episode %s discarded", run_id, episode_id)

    def lacking(
        self, activity: str, augmentation_name: str, *, versions: int = 1
    ) -> list[tuple[EpisodeSummary, int]]:
        """Episodes of ``activity`` with fewer than ``versions`` runs of the augmentation."""
        return augmentation.episodes_lacking(
            self.store, activity=activity, augmentation=augmentation_name, versions=versions
        )

    def versions(self, augmentation_name: str, episode_id: str) -> list[dict[str, Any]]:
        """The runs of one augmentation on one episode side by side, for a rating view: each
        version with its parameters, derived samples and channels, rating summary, and
        whether it is among the best (quartile rule, Wilcoxon)."""
        ranking = feedback.rank(self.store, augmentation_name, episode_id=episode_id)
        stats = {c.item: c for c in ranking.candidates}
        out = []
        for run in augmentation.list_runs(self.store, episode_id):
            if run.name != augmentation_name:
                continue
            item = f"{episode_id}/{run.id}"
            out.append(
                {
                    "run": run,
                    "item": item,
                    "channels": self.files.channels(episode_id, run.id),
                    "ratings": stats.get(item),
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
