"""Rating sessions as feedback episodes: asking people to rate is itself something the robot
lived through, so it is remembered like any other episode.

A session is an episode of activity ``feedback`` whose ``agent`` is the person rating and whose
``rated`` arguments are the episodes shown (as entities); each rating given during it is
``prov:wasGeneratedBy`` the session. Cues find it ("the last time Martina gave feedback"), and
:func:`session_ratings` lists what was answered in it.
"""

import datetime as dt
from collections.abc import Sequence

from pyoxigraph import NamedNode

from episodes import _rdf
from episodes.arguments import current_arguments
from episodes.errors import EpisodeStateError, InvalidInputError
from episodes.feedback import item_id, question_name
from episodes.lifecycle import ArgumentSpec, begin_episode, require_episode
from episodes.model import Rating
from episodes.snapshot import MemoryState, read_memory_state
from episodes.terms import check_name, participant_iri
from kg import Store

__all__ = ["FEEDBACK", "RATED_ROLE", "begin_session", "check_session", "session_ratings"]

FEEDBACK = "feedback"
"""The activity of a rating session."""
RATED_ROLE = "rated"
"""The role of an episode whose data is shown for rating in a session."""


def begin_session(
    store: Store,
    *,
    person: str,
    rated: Sequence[str] = (),
    begin: dt.datetime,
    episode_id: str | None = None,
    memory_state: MemoryState = read_memory_state,
) -> str:
    """Begin the feedback episode of ``person`` rating the data of the episodes ``rated``.

    Raises :class:`EpisodeNotFoundError` for a rated episode that does not exist.
    """
    person = check_name(person, "person")
    arguments = [ArgumentSpec("agent", person, "agent")]
    for rated_id in dict.fromkeys(rated):
        rated_episode, _, _ = require_episode(store, rated_id)
        arguments.append(ArgumentSpec(RATED_ROLE, rated_episode.value, "entity"))
    return begin_episode(
        store,
        activity=FEEDBACK,
        arguments=arguments,
        begin=begin,
        episode_id=episode_id,
        memory_state=memory_state,
    )


def check_session(store: Store, session_id: str, person: str) -> NamedNode:
    """The IRI of the running feedback episode ``session_id`` in which ``person`` rates.

    Raises :class:`EpisodeNotFoundError`; :class:`EpisodeStateError` when it has ended;
    :class:`InvalidInputError` when it is not a feedback episode or ``person`` is not its agent.
    """
    session, _, ended = require_episode(store, session_id)
    activity = _rdf.text(store.select("episodes_get", episode=session)[0], "activity")
    if activity != FEEDBACK:
        raise InvalidInputError(
            "session", session_id, f"a {FEEDBACK!r} episode (this one is {activity!r})"
        )
    if ended is not None:
        raise EpisodeStateError(
            f"session: feedback episode {session_id!r} ended at {ended.isoformat()}; "
            "begin a new session"
        )
    who = participant_iri(person, "person").value
    agents = [a for a in current_arguments(store, session) if a.role == "agent"]
    if not any(a.iri == who for a in agents):
        names = ", ".join(repr(a.value) for a in agents) or "nobody"
        raise InvalidInputError("person", person, f"the agent of session {session_id!r} ({names})")
    return session


def session_ratings(store: Store, session_id: str) -> list[Rating]:
    """The ratings given in the feedback episode ``session_id``, in the order given (revised
    answers included: a session records what was said). Raises :class:`EpisodeNotFoundError`."""
    session, _, _ = require_episode(store, session_id)
    return [
        Rating(
            id=_rdf.text(row, "rating").rsplit("/", 1)[-1],
            item=item_id(_rdf.iri(row, "item")),
            person=_rdf.text(row, "person"),
            value=_rdf.integer(row, "value"),
            time=_rdf.time(row, "time"),
            question=question_name(_rdf.iri(row, "asked")) if "asked" in row else None,
            session=session_id,
        )
        for row in store.select("episodes_session_ratings", session=session)
    ]
