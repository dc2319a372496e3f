"""IRIs of episodes and their parts, and validation of the names that go into them.

>>> episode_iri("e1").value
'https://w3id.org/engram/episode/e1'
>>> participant_iri("HyungJin").value
'https://w3id.org/engram/participant/HyungJin'
>>> participant_iri("Dr Who").value
'https://w3id.org/engram/participant/Dr%20Who'
>>> argument_kind("agent1"), argument_kind("object")
('agent', 'entity')
"""

import re
import time
import uuid
from typing import Literal
from urllib.parse import quote

from pyoxigraph import NamedNode

from episodes.errors import InvalidInputError
from ontologies.vocab import EPISODE_NS, PARTICIPANT_NS, ROLE_NS

__all__ = [
    "AGENT_ROLES",
    "ArgumentKind",
    "argument_kind",
    "check_confidence",
    "check_name",
    "episode_id_of",
    "episode_iri",
    "new_id",
    "part_iri",
    "participant_iri",
    "role_iri",
]

ArgumentKind = Literal["agent", "entity"]
AGENT_ROLES = frozenset(
    {"agent", "recipient", "speaker", "addressee", "partner", "teacher", "performer", "subject"}
)
"""Roles whose value is taken to be an agent (prov:qualifiedAssociation) unless told otherwise.
Roles named agent1, agent2, ... count too. Everything else is an entity (prov:qualifiedUsage)."""

_ID = re.compile(r"[A-Za-z0-9][A-Za-z0-9_.-]{0,127}")
_IRI_SCHEMES = ("http://", "https://", "urn:")
MAX_NAME = 1000


def new_id() -> str:
    """A fresh, unguessable identifier for an episode, run, annotation or rating.

    Ids made later sort later (a hex nanosecond prefix), so records made in the same instant
    of the injected clock still list in the order they were made.
    """
    return f"{time.time_ns():016x}{uuid.uuid4().hex[:12]}"


def check_id(value: str, field: str) -> str:
    """``value`` if it is a valid id (letters, digits, ``_.-``, up to 128 characters)."""
    if not isinstance(value, str) or not _ID.fullmatch(value):
        raise InvalidInputError(
            field,
            value,
            "an id of 1 to 128 letters, digits, '_', '.' or '-', starting with a letter or digit",
        )
    return value


def check_name(value: object, field: str) -> str:
    """``value`` stripped, if it is a non-empty string of at most 1,000 characters."""
    if not isinstance(value, str) or not value.strip() or len(value) > MAX_NAME:
        raise InvalidInputError(
            field, value, f"a non-empty string of at most {MAX_NAME} characters"
        )
    return value.strip()


def check_confidence(value: object) -> float | None:
    """``value`` as a float, if it is None or a number from 0 to 1 (an annotation's or an
    argument's confidence)."""
    if value is None:
        return None
    if isinstance(value, bool) or not isinstance(value, int | float) or not 0.0 <= value <= 1.0:
        raise InvalidInputError("confidence", value, "a number from 0 to 1")
    return float(value)


def episode_iri(episode_id: str, field: str = "episode") -> NamedNode:
    """The IRI of the episode ``episode_id``."""
    return NamedNode(EPISODE_NS + check_id(episode_id, field))


def episode_id_of(iri: NamedNode) -> str:
    """The id of an episode IRI (the inverse of :func:`episode_iri`)."""
    return iri.value.removeprefix(EPISODE_NS)


def part_iri(episode: NamedNode, *path: str) -> NamedNode:
    """The IRI of a part of an episode: ``<episode>/<path...>``; parts are deleted with it."""
    return NamedNode("/".join([episode.value, *(quote(p, safe="") for p in path)]))


def participant_iri(value: str, field: str = "value") -> NamedNode:
    """An IRI given as such (http, https, urn), or the participant IRI minted from a name."""
    value = check_name(value, field)
    if value.startswith(_IRI_SCHEMES):
        try:
            return NamedNode(value)
        except ValueError:
            raise InvalidInputError(field, value, "a valid IRI or a plain name") from None
    return NamedNode(PARTICIPANT_NS + quote(value, safe=""))


def role_iri(role: str, field: str = "role") -> NamedNode:
    """The prov:Role individual for a role name (``agent``, ``object``, ``recipient``...)."""
    return NamedNode(ROLE_NS + quote(check_name(role, field), safe=""))


def argument_kind(role: str) -> ArgumentKind:
    """``agent`` for agent-like roles (see :data:`AGENT_ROLES`), else ``entity``."""
    name = role.strip().lower()
    if name in AGENT_ROLES or re.fullmatch(r"agent\d*", name):
        return "agent"
    return "entity"
