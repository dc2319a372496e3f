"""A-posteriori augmentation: versioned runs of a module over an episode, derived samples
linked to the recorded frames they come from, and "which episodes lack an augmentation".
"""

import datetime as dt
import json
from collections.abc import Collection, Mapping, Sequence
from dataclasses import dataclass
from typing import Any

from pyoxigraph import Literal, NamedNode

from episodes import _rdf
from episodes.errors import (
    EpisodeNotFoundError,
    EpisodeStateError,
    InvalidInputError,
    NotFoundError,
)
from episodes.lifecycle import episode_times, participant
from episodes.model import AugmentationRun, DerivedSample, EpisodeSummary
from episodes.streamlink import read_descriptors
from episodes.terms import check_id, check_name, episode_id_of, episode_iri, new_id, part_iri
from episodes.times import to_literal
from kg import Store
from ontologies.vocab import (
    AUGMENTATION_NAME,
    AUGMENTATION_RUN,
    AUGMENTS,
    DERIVED_CHANNEL,
    DERIVED_SAMPLE,
    EPISODES,
    FRAME,
    FRAME_NUMBER,
    FRAME_OF,
    PARAMETERS,
    PROV_ENDED_AT_TIME,
    PROV_SOFTWARE_AGENT,
    PROV_STARTED_AT_TIME,
    PROV_USED,
    PROV_WAS_ASSOCIATED_WITH,
    PROV_WAS_DERIVED_FROM,
    PROV_WAS_GENERATED_BY,
    RDF_TYPE,
    RUN_VERSION,
    SOURCE_CHANNEL,
)

__all__ = [
    "DerivedSpec",
    "add_derived",
    "check_derived",
    "end_run",
    "episodes_lacking",
    "get_run",
    "list_runs",
    "run_iri",
    "start_run",
]

MAX_FRAME = 2**63 - 1


@dataclass(frozen=True)
class DerivedSpec:
    """A derived sample to record: computed from ``frame`` of ``source_channel``, its data in
    ``derived_channel`` of the run's stream file."""

    frame: int
    source_channel: str
    derived_channel: str


def run_iri(episode_id: str, run_id: str) -> NamedNode:
    return part_iri(episode_iri(episode_id), "run", check_id(run_id, "run"))


def _parameters(parameters: Mapping[str, Any] | None) -> str:
    if parameters is None:
        return "{}"
    if not isinstance(parameters, Mapping):
        raise InvalidInputError("parameters", parameters, "a JSON object")
    try:
        return json.dumps(dict(parameters), sort_keys=True, allow_nan=False)
    except (TypeError, ValueError):
        raise InvalidInputError(
            "parameters", repr(parameters), "a JSON object of JSON values"
        ) from None


def start_run(
    store: Store,
    episode_id: str,
    *,
    name: str,
    producer: str,
    parameters: Mapping[str, Any] | None = None,
    started: dt.datetime,
) -> AugmentationRun:
    """Open a new run of augmentation ``name`` on an episode; its version is one more than the
    versions of ``name`` already on the episode. Raises :class:`EpisodeNotFoundError`."""
    name = check_name(name, "name")
    producer = check_name(producer, "producer")
    text = _parameters(parameters)
    run_id = new_id()
    episode = episode_iri(episode_id)
    with store.transaction() as tx:
        if episode_times(store, episode) is None:
            raise EpisodeNotFoundError(episode_id)
        versions = [
            _rdf.integer(r, "version")
            for r in store.select("episodes_runs", episode=episode)
            if _rdf.text(r, "name") == name
        ]
        version = max(versions, default=0) + 1
        run = run_iri(episode_id, run_id)
        tx.insert(run, RDF_TYPE, AUGMENTATION_RUN, EPISODES)
        tx.insert(run, AUGMENTS, episode, EPISODES)
        tx.insert(run, AUGMENTATION_NAME, Literal(name), EPISODES)
        tx.insert(run, RUN_VERSION, Literal(version), EPISODES)
        tx.insert(run, PARAMETERS, Literal(text), EPISODES)
        tx.insert(run, PROV_STARTED_AT_TIME, to_literal(started), EPISODES)
        agent = participant(tx, producer, PROV_SOFTWARE_AGENT, "producer")
        tx.insert(run, PROV_WAS_ASSOCIATED_WITH, agent, EPISODES)
        for descriptor in read_descriptors(store, episode):
            stream = part_iri(episode, "stream", descriptor.channel.strip("/") or "root")
            tx.insert(run, PROV_USED, stream, EPISODES)
    return AugmentationRun(
        id=run_id,
        episode_id=episode_id,
        name=name,
        version=version,
        producer=producer,
        parameters=json.loads(text),
        started=started,
    )


def list_runs(store: Store, episode_id: str) -> list[AugmentationRun]:
    """The augmentation runs of an episode, by name and version."""
    episode = episode_iri(episode_id)
    if episode_times(store, episode) is None:
        raise EpisodeNotFoundError(episode_id)
    return [
        AugmentationRun(
            id=_rdf.text(r, "run").rsplit("/", 1)[-1],
            episode_id=episode_id,
            name=_rdf.text(r, "name"),
            version=_rdf.integer(r, "version"),
            producer=_rdf.text(r, "producer"),
            parameters=json.loads(_rdf.text(r, "parameters")),
            started=_rdf.time(r, "started"),
            ended=_rdf.opt_time(r, "ended"),
            samples=_rdf.integer(r, "samples"),
        )
        for r in store.select("episodes_runs", episode=episode)
    ]


def get_run(store: Store, episode_id: str, run_id: str) -> AugmentationRun:
    """One run; raises :class:`NotFoundError` if the episode has no such run."""
    check_id(run_id, "run")
    for run in list_runs(store, episode_id):
        if run.id == run_id:
            return run
    raise NotFoundError(f"run: episode {episode_id!r} has no augmentation run {run_id!r}")


def _recorded_channels(store: Store, episode: NamedNode) -> set[str]:
    """The channels (topics) and provider names of an episode's recorded streams."""
    return {name for d in read_descriptors(store, episode) for name in (d.channel, d.provider)}


RecordedFrames = Mapping[int, Collection[str]]
"""Frame number -> the providers and channels (topics) that have a sample at that frame."""


def _check_specs(
    specs: Sequence[DerivedSpec], channels: set[str], recorded: RecordedFrames | None = None
) -> None:
    for i, spec in enumerate(specs):
        if (
            isinstance(spec.frame, bool)
            or not isinstance(spec.frame, int)
            or not 0 <= spec.frame <= MAX_FRAME
        ):
            raise InvalidInputError(f"samples[{i}].frame", spec.frame, "a frame number >= 0")
        check_name(spec.source_channel, f"samples[{i}].source_channel")
        check_name(spec.derived_channel, f"samples[{i}].derived_channel")
        if channels and spec.source_channel not in channels:
            raise InvalidInputError(
                f"samples[{i}].source_channel",
                spec.source_channel,
                f"a recorded channel of the episode: {', '.join(sorted(channels))}",
            )
        if recorded is not None:
            _check_frame(i, spec, recorded)


def _check_frame(i: int, spec: DerivedSpec, recorded: RecordedFrames) -> None:
    """A derived sample must come from a recorded frame holding its source channel."""
    if not recorded:
        raise InvalidInputError(
            f"samples[{i}].frame", spec.frame, "a recorded frame; the episode has no recording"
        )
    held = recorded.get(spec.frame)
    if held is None:
        raise InvalidInputError(
            f"samples[{i}].frame",
            spec.frame,
            f"a recorded frame of the episode, {min(recorded)} to {max(recorded)}",
        )
    if spec.source_channel not in held:
        raise InvalidInputError(
            f"samples[{i}].source_channel",
            spec.source_channel,
            f"a channel with data at frame {spec.frame}: {', '.join(sorted(held))}",
        )


def check_derived(
    store: Store,
    episode_id: str,
    run_id: str,
    specs: Sequence[DerivedSpec],
    recorded: RecordedFrames | None = None,
) -> None:
    """Raise what :func:`add_derived` would raise for these samples, writing nothing."""
    current = get_run(store, episode_id, run_id)
    if current.ended is not None:
        raise EpisodeStateError(f"run: run {run_id!r} has ended; start a new run")
    _check_specs(specs, _recorded_channels(store, episode_iri(episode_id)), recorded)


def add_derived(
    store: Store,
    episode_id: str,
    run_id: str,
    specs: Sequence[DerivedSpec],
    recorded: RecordedFrames | None = None,
) -> list[DerivedSample]:
    """Record derived samples of an open run, each ``prov:wasDerivedFrom`` its source frame.

    With ``recorded`` (what the episode's stream file holds, frame by frame) each sample must
    name a recorded frame holding its source channel. Raises :class:`NotFoundError` for an
    unknown run, :class:`EpisodeStateError` for a run that has ended, and
    :class:`InvalidInputError` (nothing written) for a bad sample, naming frame and channel.
    """
    episode = episode_iri(episode_id)
    run = run_iri(episode_id, run_id)
    with store.transaction() as tx:
        current = get_run(store, episode_id, run_id)
        if current.ended is not None:
            raise EpisodeStateError(f"run: run {run_id!r} has ended; start a new run")
        channels = _recorded_channels(store, episode)
        _check_specs(specs, channels, recorded)
        samples = []
        for i, spec in enumerate(specs, start=current.samples):
            frame = part_iri(episode, "frame", str(spec.frame))
            tx.insert(frame, RDF_TYPE, FRAME, EPISODES)
            tx.insert(frame, FRAME_OF, episode, EPISODES)
            tx.insert(frame, FRAME_NUMBER, Literal(spec.frame), EPISODES)
            sample = part_iri(run, "sample", str(i))
            tx.insert(sample, RDF_TYPE, DERIVED_SAMPLE, EPISODES)
            tx.insert(sample, PROV_WAS_GENERATED_BY, run, EPISODES)
            tx.insert(sample, PROV_WAS_DERIVED_FROM, frame, EPISODES)
            tx.insert(sample, SOURCE_CHANNEL, Literal(spec.source_channel), EPISODES)
            tx.insert(sample, DERIVED_CHANNEL, Literal(spec.derived_channel), EPISODES)
            samples.append(
                DerivedSample(str(i), run_id, spec.frame, spec.source_channel, spec.derived_channel)
            )
    return samples


def end_run(store: Store, episode_id: str, run_id: str, *, ended: dt.datetime) -> AugmentationRun:
    """Close a run; raises :class:`EpisodeStateError` if it has ended already."""
    with store.transaction() as tx:
        current = get_run(store, episode_id, run_id)
        if current.ended is not None:
            raise EpisodeStateError(f"run: run {run_id!r} ended already")
        tx.insert(run_iri(episode_id, run_id), PROV_ENDED_AT_TIME, to_literal(ended), EPISODES)
    return get_run(store, episode_id, run_id)


def episodes_lacking(
    store: Store, *, activity: str, augmentation: str, versions: int = 1
) -> list[tuple[EpisodeSummary, int]]:
    """The episodes of ``activity`` with fewer than ``versions`` runs of ``augmentation``
    (one query), oldest first, each with the number of runs it has."""
    activity = check_name(activity, "activity")
    augmentation = check_name(augmentation, "augmentation")
    if isinstance(versions, bool) or not isinstance(versions, int) or not 1 <= versions <= 1000:
        raise InvalidInputError("versions", versions, "an integer from 1 to 1000")
    rows = store.select(
        "episodes_lacking_augmentation",
        activity=Literal(activity),
        augmentation=Literal(augmentation),
        versions=Literal(versions),
    )
    return [
        (
            EpisodeSummary(
                id=episode_id_of(_rdf.iri(r, "episode")),
                activity=activity,
                activity_type=_rdf.opt_text(r, "type"),
                begin=_rdf.time(r, "begin"),
                end=_rdf.opt_time(r, "end"),
            ),
            _rdf.integer(r, "runs"),
        )
        for r in rows
    ]
