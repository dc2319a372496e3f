"""Episodes in the graph: begin, end, annotate, read, link scenes, delete.

Every write is one transaction; the checks it depends on run inside the transaction block,
which holds the store's write lock, so no other writer can slip in between check and write.
"""

import datetime as dt
import logging
from collections.abc import Iterable, Sequence
from dataclasses import dataclass

from pyoxigraph import Literal, NamedNode

from episodes import _rdf
from episodes.cue_index import write_keys
from episodes.errors import EpisodeNotFoundError, EpisodeStateError, InvalidInputError
from episodes.model import Annotation, Argument, Episode, MemorySnapshot, StreamDescriptor
from episodes.snapshot import MemoryState, load_snapshot, read_memory_state, write_snapshot
from episodes.streamlink import read_descriptors, write_descriptors
from episodes.terms import (
    ArgumentKind,
    argument_kind,
    check_confidence,
    check_name,
    episode_iri,
    new_id,
    part_iri,
    participant_iri,
    role_iri,
)
from episodes.time_index import drop_activity_ends, end_days, write_activity_ends, write_days
from episodes.times import parse_time, to_literal
from episodes.world import current_scene, write_world
from kg import Store, Transaction
from ontologies.vocab import (
    ACTIVITY_NAME,
    ACTIVITY_TYPE,
    ANNOTATES,
    ANNOTATION,
    ANNOTATION_KEY,
    ANNOTATION_VALUE,
    CONFIDENCE,
    EPISODE,
    EPISODES,
    EPISODIC,
    HAPPENED_DURING,
    PROV_AGENT,
    PROV_AGENT_PROPERTY,
    PROV_ASSOCIATION,
    PROV_ENDED_AT_TIME,
    PROV_ENTITY,
    PROV_ENTITY_PROPERTY,
    PROV_GENERATED_AT_TIME,
    PROV_HAD_ROLE,
    PROV_QUALIFIED_ASSOCIATION,
    PROV_QUALIFIED_USAGE,
    PROV_ROLE,
    PROV_STARTED_AT_TIME,
    PROV_USAGE,
    PROV_USED,
    PROV_WAS_ASSOCIATED_WITH,
    PROV_WAS_ATTRIBUTED_TO,
    RANGE_END,
    RANGE_START,
    RDF_TYPE,
    RDFS_LABEL,
    STATE_AT_BEGIN,
    STATE_AT_END,
)

__all__ = [
    "ArgumentSpec",
    "add_annotation",
    "begin_episode",
    "delete_episode_triples",
    "end_episode",
    "episode_times",
    "get_episode",
    "link_scene",
    "participant",
    "read_argument",
    "require_episode",
]

log = logging.getLogger(__name__)


@dataclass(frozen=True)
class ArgumentSpec:
    """A role-labelled argument to record: ``ArgumentSpec("agent", "HyungJin")``.

    ``kind`` says whether the value is an agent (a person, the robot, a module: recorded as a
    ``prov:qualifiedAssociation``) or an entity (an object: a ``prov:qualifiedUsage``); by
    default it follows the role (see :data:`episodes.terms.AGENT_ROLES`).
    """

    role: str
    value: str
    kind: ArgumentKind | None = None


def participant(tx: Transaction, value: str, kind: NamedNode, field: str) -> NamedNode:
    """The IRI of a named participant, typed ``kind`` and labelled with its name."""
    node = participant_iri(value, field)
    tx.insert(node, RDF_TYPE, kind, EPISODES)
    if not value.startswith(("http://", "https://", "urn:")):
        tx.insert(node, RDFS_LABEL, Literal(value.strip()), EPISODES)
    return node


def _check_arguments(arguments: Sequence[ArgumentSpec]) -> list[tuple[str, str, ArgumentKind]]:
    checked = []
    seen = set()
    for i, argument in enumerate(arguments):
        role = check_name(argument.role, f"arguments[{i}].role")
        value = check_name(argument.value, f"arguments[{i}].value")
        kind = argument.kind or argument_kind(role)
        if kind not in ("agent", "entity"):
            raise InvalidInputError(f"arguments[{i}].kind", kind, "'agent' or 'entity'")
        if (role, value) in seen:
            raise InvalidInputError(
                f"arguments[{i}]", f"{role}={value}", "each role and value once"
            )
        seen.add((role, value))
        checked.append((role, value, kind))
    return checked


def begin_episode(
    store: Store,
    *,
    activity: str,
    activity_type: str | None = None,
    arguments: Sequence[ArgumentSpec] = (),
    begin: dt.datetime | str,
    episode_id: str | None = None,
    end: dt.datetime | str | None = None,
    streams: Iterable[StreamDescriptor] = (),
    snapshots: bool = True,
    memory_state: MemoryState = read_memory_state,
) -> str:
    """Record that an episode began, with a snapshot of the scene memory; return its id.

    With ``end`` (and ``streams``) a finished episode is recorded whole, in the same
    transaction, e.g. one imported from a bag; ``snapshots=False`` leaves out the scene
    memory's state, which is not known for a past episode; ``memory_state`` reads it. Raises
    :class:`InvalidInputError` for a bad name, time or argument, and :class:`EpisodeStateError`
    if ``episode_id`` is taken.
    """

    activity = check_name(activity, "activity")
    kind_name = check_name(activity_type, "type") if activity_type is not None else None
    started = parse_time(begin, "begin")
    ended = parse_time(end, "end") if end is not None else None
    if ended is not None and ended < started:
        raise InvalidInputError(
            "end", ended.isoformat(), f"a time not before the begin {started.isoformat()}"
        )
    checked = _check_arguments(arguments)
    episode_id = episode_id or new_id()
    episode = episode_iri(episode_id, "id")
    # read before the write lock is taken: the scene memory takes its own lock, then the store's
    snapshot = memory_state(store) if snapshots else None
    scene = current_scene(store) if snapshots else None
    with store.transaction() as tx:
        if episode_times(store, episode) is not None:
            raise EpisodeStateError(f"id: an episode {episode_id!r} already exists")
        tx.insert(episode, RDF_TYPE, EPISODE, EPISODES)
        tx.insert(episode, ACTIVITY_NAME, Literal(activity), EPISODES)
        if kind_name is not None:
            tx.insert(episode, ACTIVITY_TYPE, Literal(kind_name), EPISODES)
        tx.insert(episode, PROV_STARTED_AT_TIME, to_literal(started), EPISODES)
        write_days(tx, episode, started, ended)
        write_activity_ends(tx, store, episode, activity, started)
        for i, (role, value, kind) in enumerate(checked):
            link = part_iri(episode, "argument", str(i))
            role_node = role_iri(role)
            tx.insert(role_node, RDF_TYPE, PROV_ROLE, EPISODES)
            tx.insert(role_node, RDFS_LABEL, Literal(role), EPISODES)
            if kind == "agent":
                who = participant(tx, value, PROV_AGENT, f"arguments[{i}].value")
                tx.insert(episode, PROV_WAS_ASSOCIATED_WITH, who, EPISODES)
                tx.insert(episode, PROV_QUALIFIED_ASSOCIATION, link, EPISODES)
                tx.insert(link, RDF_TYPE, PROV_ASSOCIATION, EPISODES)
                tx.insert(link, PROV_AGENT_PROPERTY, who, EPISODES)
            else:
                what = participant(tx, value, PROV_ENTITY, f"arguments[{i}].value")
                tx.insert(episode, PROV_USED, what, EPISODES)
                tx.insert(episode, PROV_QUALIFIED_USAGE, link, EPISODES)
                tx.insert(link, RDF_TYPE, PROV_USAGE, EPISODES)
                tx.insert(link, PROV_ENTITY_PROPERTY, what, EPISODES)
            tx.insert(link, PROV_HAD_ROLE, role_node, EPISODES)
            write_keys(tx, link, activity, role_node, participant_iri(value))
        if snapshot is not None:
            state = part_iri(episode, "state", "begin")
            tx.insert(episode, STATE_AT_BEGIN, state, EPISODES)
            write_snapshot(tx, state, snapshot)
            write_world(tx, state, scene, (participant_iri(v) for _, v, _ in checked))
        if ended is not None:
            tx.insert(episode, PROV_ENDED_AT_TIME, to_literal(ended), EPISODES)
            write_descriptors(tx, episode, streams)
    log.info("episode %s began: %s", episode_id, activity)
    return episode_id


def episode_times(
    store: Store, episode: NamedNode
) -> tuple[dt.datetime, dt.datetime | None] | None:
    """(begin, end) of an episode, or ``None`` if there is no such episode."""
    rows = store.select("episodes_get", episode=episode)
    if not rows:
        return None
    return _rdf.time(rows[0], "begin"), _rdf.opt_time(rows[0], "end")


def require_episode(
    store: Store, episode_id: str
) -> tuple[NamedNode, dt.datetime, dt.datetime | None]:
    """The episode's IRI, begin and end; raises :class:`EpisodeNotFoundError`."""
    episode = episode_iri(episode_id)
    times = episode_times(store, episode)
    if times is None:
        raise EpisodeNotFoundError(episode_id)
    return episode, times[0], times[1]


def end_episode(
    store: Store,
    episode_id: str,
    *,
    end: dt.datetime | str,
    streams: Iterable[StreamDescriptor] = (),
    memory_state: MemoryState = read_memory_state,
) -> None:
    """Record the end of a running episode, the memory's state then (read by
    ``memory_state``), and its streams.

    Raises :class:`EpisodeNotFoundError`, :class:`InvalidInputError` for an end before the
    begin, and :class:`EpisodeStateError` if the episode has already ended.
    """

    ended = parse_time(end, "end")
    snapshot = memory_state(store)  # before the write lock, as in begin_episode
    scene = current_scene(store)
    with store.transaction() as tx:
        episode, began, already = require_episode(store, episode_id)
        if already is not None:
            raise EpisodeStateError(
                f"end: episode {episode_id!r} already ended at {already.isoformat()}"
            )
        if ended < began:
            raise InvalidInputError(
                "end", ended.isoformat(), f"a time not before the begin {began.isoformat()}"
            )
        tx.insert(episode, PROV_ENDED_AT_TIME, to_literal(ended), EPISODES)
        end_days(tx, episode, began, ended)
        state = part_iri(episode, "state", "end")
        tx.insert(episode, STATE_AT_END, state, EPISODES)
        write_snapshot(tx, state, snapshot)
        present = {
            _rdf.iri(r, "participant") for r in store.select("episodes_arguments", episode=episode)
        }
        write_world(tx, state, scene, sorted(present, key=lambda n: n.value))
        write_descriptors(tx, episode, streams)
    log.info("episode %s ended", episode_id)


def add_annotation(
    store: Store,
    episode_id: str,
    *,
    key: str,
    value: str,
    created: dt.datetime,
    author: str | None = None,
    confidence: float | None = None,
    start: dt.datetime | str | None = None,
    end: dt.datetime | str | None = None,
) -> Annotation:
    """Annotate an episode, as a whole or over ``start``..``end`` inside it; return the record.

    Raises :class:`EpisodeNotFoundError`, and :class:`InvalidInputError` for a confidence
    outside [0, 1] or a range that is reversed or not inside the episode.
    """
    key = check_name(key, "key")
    value = check_name(value, "value")
    author = check_name(author, "author") if author is not None else None
    confidence = check_confidence(confidence)
    range_start = parse_time(start, "start") if start is not None else None
    range_end = parse_time(end, "end") if end is not None else None
    if range_start and range_end and range_end < range_start:
        raise InvalidInputError(
            "end", range_end.isoformat(), f"a time not before start {range_start.isoformat()}"
        )
    annotation_id = new_id()
    with store.transaction() as tx:
        episode, began, ended = require_episode(store, episode_id)
        for name, moment in (("start", range_start), ("end", range_end)):
            if moment is not None and (moment < began or (ended is not None and moment > ended)):
                window = f"{began.isoformat()} .. {ended.isoformat() if ended else 'now'}"
                raise InvalidInputError(
                    name, moment.isoformat(), f"a time inside the episode, {window}"
                )
        node = part_iri(episode, "annotation", annotation_id)
        tx.insert(node, RDF_TYPE, ANNOTATION, EPISODES)
        tx.insert(node, ANNOTATES, episode, EPISODES)
        tx.insert(node, ANNOTATION_KEY, Literal(key), EPISODES)
        tx.insert(node, ANNOTATION_VALUE, Literal(value), EPISODES)
        tx.insert(node, PROV_GENERATED_AT_TIME, to_literal(created), EPISODES)
        if author is not None:
            tx.insert(
                node,
                PROV_WAS_ATTRIBUTED_TO,
                participant(tx, author, PROV_AGENT, "author"),
                EPISODES,
            )
        if confidence is not None:
            tx.insert(node, CONFIDENCE, Literal(confidence), EPISODES)
        if range_start is not None:
            tx.insert(node, RANGE_START, to_literal(range_start), EPISODES)
        if range_end is not None:
            tx.insert(node, RANGE_END, to_literal(range_end), EPISODES)
    return Annotation(
        id=annotation_id,
        key=key,
        value=value,
        created=created,
        author=author,
        confidence=confidence,
        start=range_start,
        end=range_end,
    )


def link_scene(store: Store, episode_id: str, scene: str) -> None:
    """Record in the ``episodic`` graph that the experienced scene ``scene`` happened during
    the episode (what the scene memory does itself with ``engram:happenedDuring``).

    Raises :class:`EpisodeNotFoundError`, and :class:`InvalidInputError` when ``scene`` is not
    an experienced scene already stored (``engram:ExperiencedScene``).
    """
    try:
        scene_node = NamedNode(check_name(scene, "scene"))
    except ValueError:
        raise InvalidInputError("scene", scene, "the IRI of an experienced scene") from None
    with store.transaction() as tx:
        episode, _, _ = require_episode(store, episode_id)
        # a link to a scene not stored yet would be taken over by the next scene minted with
        # that IRI, so only scenes the scene memory already holds can be linked
        if not store.ask("episodes_scene_exists", scene=scene_node):
            raise InvalidInputError(
                "scene", scene, "the IRI of an experienced scene the scene memory has stored"
            )
        tx.insert(scene_node, HAPPENED_DURING, episode, EPISODIC)


def read_argument(row: _rdf.Row) -> Argument:
    """The argument a row of the ``episodes_arguments`` query describes."""
    return Argument(
        role=_rdf.text(row, "role"),
        value=_rdf.opt_text(row, "label") or _rdf.text(row, "participant"),
        kind="agent" if _rdf.text(row, "kind") == "agent" else "entity",
        iri=_rdf.text(row, "participant"),
        id=_rdf.text(row, "link").rsplit("/", 1)[-1],
        author=_rdf.opt_text(row, "author"),
        asserted=_rdf.opt_time(row, "asserted"),
        confidence=_rdf.opt_number(row, "confidence"),
    )


def get_episode(store: Store, episode_id: str) -> Episode:
    """Everything the graph holds about an episode; raises :class:`EpisodeNotFoundError`."""

    episode = episode_iri(episode_id)
    rows = store.select("episodes_get", episode=episode)
    if not rows:
        raise EpisodeNotFoundError(episode_id)
    row = rows[0]
    arguments = tuple(read_argument(r) for r in store.select("episodes_arguments", episode=episode))
    annotations = tuple(
        Annotation(
            id=_rdf.text(r, "annotation").rsplit("/", 1)[-1],
            key=_rdf.text(r, "key"),
            value=_rdf.text(r, "value"),
            created=_rdf.time(r, "created"),
            author=_rdf.opt_text(r, "author"),
            confidence=_rdf.opt_number(r, "confidence"),
            start=_rdf.opt_time(r, "start"),
            end=_rdf.opt_time(r, "end"),
        )
        for r in store.select("episodes_annotations", episode=episode)
    )
    return Episode(
        id=episode_id,
        iri=episode.value,
        activity=_rdf.text(row, "activity"),
        activity_type=_rdf.opt_text(row, "type"),
        begin=_rdf.time(row, "begin"),
        end=_rdf.opt_time(row, "end"),
        arguments=arguments,
        state_at_begin=_snapshot(store, row, "stateAtBegin"),
        state_at_end=_snapshot(store, row, "stateAtEnd"),
        annotations=annotations,
        streams=read_descriptors(store, episode),
        scenes=tuple(
            _rdf.text(r, "scene") for r in store.select("episodes_scenes", episode=episode)
        ),
    )


def _snapshot(store: Store, row: _rdf.Row, name: str) -> MemorySnapshot | None:
    return load_snapshot(store, _rdf.iri(row, name)) if name in row else None


def delete_episode_triples(tx: Transaction, store: Store, episode_id: str) -> None:
    """Queue, in ``tx``, the deletion of every triple of an episode: its own nodes and parts,
    the participants only it used, and the scene links to it. Call inside the transaction
    block; raises :class:`EpisodeNotFoundError`."""
    episode, _, _ = require_episode(store, episode_id)
    drop_activity_ends(tx, store, episode)
    for name in ("episodes_owned_nodes", "episodes_orphaned_participants"):
        for row in store.select(name, episode=episode):
            tx.delete_matching(_rdf.iri(row, "node"), graph=EPISODES)
    tx.delete_matching(None, HAPPENED_DURING, episode, graph=EPISODIC)
