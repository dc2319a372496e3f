"""Arguments after the fact: add, replace and remove an episode's role-labelled arguments.

In the paper, an interaction begun with an unknown partner gets its agent later (face
recognition names Martina with confidence 0.92). Each assertion is a qualified association
(an agent) or usage (an entity) of the episode, attributed to its author
(``prov:wasAttributedTo``) at a time (``prov:generatedAtTime``) with a confidence
(``engram:argumentConfidence``). Removing one marks it ``prov:invalidatedAtTime`` and
``engram:retractedBy`` its author; replacing one does that and links the new one to it
(``prov:wasRevisionOf``). Nothing is deleted, so the history stays in the graph, and cues read
only the arguments still valid, so they see a change at once.
"""

import datetime as dt
from dataclasses import dataclass

from pyoxigraph import Literal, NamedNode

from episodes import _rdf
from episodes.cue_index import drop_keys, write_keys
from episodes.errors import InvalidInputError, NotFoundError
from episodes.lifecycle import participant, read_argument, require_episode
from episodes.model import Argument
from episodes.terms import (
    ArgumentKind,
    argument_kind,
    check_confidence,
    check_name,
    new_id,
    part_iri,
    participant_iri,
    role_iri,
)
from episodes.times import to_literal
from kg import Store, Transaction
from ontologies.vocab import (
    ARGUMENT_CONFIDENCE,
    EPISODES,
    PROV_AGENT,
    PROV_AGENT_PROPERTY,
    PROV_ASSOCIATION,
    PROV_ENTITY,
    PROV_ENTITY_PROPERTY,
    PROV_GENERATED_AT_TIME,
    PROV_HAD_ROLE,
    PROV_INVALIDATED_AT_TIME,
    PROV_QUALIFIED_ASSOCIATION,
    PROV_QUALIFIED_USAGE,
    PROV_ROLE,
    PROV_USAGE,
    PROV_USED,
    PROV_WAS_ASSOCIATED_WITH,
    PROV_WAS_ATTRIBUTED_TO,
    PROV_WAS_REVISION_OF,
    RDF_TYPE,
    RDFS_LABEL,
    RETRACTED_BY,
)

__all__ = ["Assertion", "add_argument", "current_arguments", "remove_argument"]


@dataclass(frozen=True)
class Assertion:
    """Who says so, when, and how sure: the provenance of an argument given after the fact."""

    time: dt.datetime
    author: str | None = None
    confidence: float | None = None

    def checked(self) -> "Assertion":
        author = check_name(self.author, "author") if self.author is not None else None
        return Assertion(self.time, author, check_confidence(self.confidence))


@dataclass(frozen=True)
class _Current:
    link: NamedNode
    argument: Argument


def current_arguments(store: Store, episode: NamedNode) -> list[Argument]:
    """The arguments of an episode still valid, oldest assertion first."""
    return [c.argument for c in _current(store, episode)]


def _current(store: Store, episode: NamedNode) -> list[_Current]:
    return [
        _Current(link=_rdf.iri(r, "link"), argument=read_argument(r))
        for r in store.select("episodes_arguments", episode=episode)
    ]


def _activity(store: Store, episode: NamedNode) -> str:
    return _rdf.text(store.select("episodes_get", episode=episode)[0], "activity")


def _matching(current: list[_Current], role: str, value: str | None, field: str) -> list[_Current]:
    who = participant_iri(value, field).value if value is not None else None
    return [
        c for c in current if c.argument.role == role and (who is None or c.argument.iri == who)
    ]


def add_argument(
    store: Store,
    episode_id: str,
    *,
    role: str,
    value: str,
    kind: ArgumentKind | None = None,
    assertion: Assertion,
    replace: bool = False,
    replaces: str | None = None,
) -> Argument:
    """Add ``value`` in ``role`` to an episode; with ``replace``, the arguments now in that role
    (or only the one whose value is ``replaces``) are retracted and the new one revises them.

    Raises :class:`EpisodeNotFoundError`, :class:`InvalidInputError` for a bad name, kind or
    confidence or when the same value already holds the role, and :class:`NotFoundError` when
    ``replace`` finds nothing to replace.
    """
    role = check_name(role, "role")
    value = check_name(value, "value")
    kind = kind or argument_kind(role)
    if kind not in ("agent", "entity"):
        raise InvalidInputError("kind", kind, "'agent' or 'entity'")
    assertion = assertion.checked()
    link_id = new_id()
    with store.transaction() as tx:
        episode, _, _ = require_episode(store, episode_id)
        activity = _activity(store, episode)
        current = _current(store, episode)
        old = _matching(current, role, replaces, "replaces") if replace else []
        if replace and not old:
            what = f"{role}={replaces}" if replaces is not None else f"an argument in role {role!r}"
            raise NotFoundError(f"replace: episode {episode_id!r} has no {what} to replace")
        remaining = [c for c in current if c not in old]
        if _matching(remaining, role, value, "value"):
            raise InvalidInputError(
                "value", value, f"a value not already in role {role!r} of the episode"
            )
        newcomer = _Current(
            link=NamedNode(part_iri(episode, "argument", link_id).value),
            argument=Argument(role, value, kind, participant_iri(value, "value").value),
        )
        for gone in old:
            _retract(tx, episode, activity, gone, [*remaining, newcomer], assertion)
        link = part_iri(episode, "argument", link_id)
        role_node = role_iri(role)
        tx.insert(role_node, RDF_TYPE, PROV_ROLE, EPISODES)
        tx.insert(role_node, RDFS_LABEL, Literal(role), EPISODES)
        if kind == "agent":
            who = participant(tx, value, PROV_AGENT, "value")
            tx.insert(episode, PROV_WAS_ASSOCIATED_WITH, who, EPISODES)
            tx.insert(episode, PROV_QUALIFIED_ASSOCIATION, link, EPISODES)
            tx.insert(link, RDF_TYPE, PROV_ASSOCIATION, EPISODES)
            tx.insert(link, PROV_AGENT_PROPERTY, who, EPISODES)
        else:
            who = participant(tx, value, PROV_ENTITY, "value")
            tx.insert(episode, PROV_USED, who, EPISODES)
            tx.insert(episode, PROV_QUALIFIED_USAGE, link, EPISODES)
            tx.insert(link, RDF_TYPE, PROV_USAGE, EPISODES)
            tx.insert(link, PROV_ENTITY_PROPERTY, who, EPISODES)
        tx.insert(link, PROV_HAD_ROLE, role_node, EPISODES)
        write_keys(tx, link, activity, role_node, who)
        tx.insert(link, PROV_GENERATED_AT_TIME, to_literal(assertion.time), EPISODES)
        if assertion.author is not None:
            author = participant(tx, assertion.author, PROV_AGENT, "author")
            tx.insert(link, PROV_WAS_ATTRIBUTED_TO, author, EPISODES)
        if assertion.confidence is not None:
            tx.insert(link, ARGUMENT_CONFIDENCE, Literal(assertion.confidence), EPISODES)
        for gone in old:
            tx.insert(link, PROV_WAS_REVISION_OF, gone.link, EPISODES)
    return Argument(
        role=role,
        value=value,
        kind=kind,
        iri=who.value,
        id=link_id,
        author=assertion.author,
        asserted=assertion.time,
        confidence=assertion.confidence,
    )


def remove_argument(
    store: Store, episode_id: str, *, role: str, value: str | None = None, assertion: Assertion
) -> list[Argument]:
    """Retract the arguments in ``role`` (only ``value``'s when given); returns them.

    Raises :class:`EpisodeNotFoundError`, and :class:`NotFoundError` when nothing matches.
    """
    role = check_name(role, "role")
    assertion = assertion.checked()
    with store.transaction() as tx:
        episode, _, _ = require_episode(store, episode_id)
        activity = _activity(store, episode)
        current = _current(store, episode)
        gone = _matching(current, role, value, "value")
        if not gone:
            what = f"{role}={value}" if value is not None else f"an argument in role {role!r}"
            raise NotFoundError(f"argument: episode {episode_id!r} has no {what}")
        remaining = [c for c in current if c not in gone]
        for old in gone:
            _retract(tx, episode, activity, old, remaining, assertion)
    return [g.argument for g in gone]


def _retract(
    tx: Transaction,
    episode: NamedNode,
    activity: str,
    gone: _Current,
    remaining: list[_Current],
    assertion: Assertion,
) -> None:
    """Mark an argument no longer valid; drop the episode's unqualified link to its participant
    unless another valid argument keeps the same participant in the same kind."""
    tx.insert(gone.link, PROV_INVALIDATED_AT_TIME, to_literal(assertion.time), EPISODES)
    drop_keys(tx, gone.link, activity, role_iri(gone.argument.role), NamedNode(gone.argument.iri))
    if assertion.author is not None:
        author = participant(tx, assertion.author, PROV_AGENT, "author")
        tx.insert(gone.link, RETRACTED_BY, author, EPISODES)
    kept = any(
        c.argument.iri == gone.argument.iri and c.argument.kind == gone.argument.kind
        for c in remaining
    )
    if not kept:
        shortcut = PROV_WAS_ASSOCIATED_WITH if gone.argument.kind == "agent" else PROV_USED
        tx.delete(episode, shortcut, NamedNode(gone.argument.iri), EPISODES)
