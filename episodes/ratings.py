"""An episode memory's feedback: people's 1-10 ratings of augmentation runs (or of their derived
samples), given alone or in a rating session, and the ranking of the rated runs.

The ratings themselves are :mod:`episodes.feedback`; a rating session is a feedback episode
(:mod:`episodes.sessions`).
"""

import datetime as dt
from collections.abc import Sequence

from episodes import feedback, lifecycle, sessions
from episodes.feedback import Ranking
from episodes.model import Episode, Rating
from episodes.snapshot import MemoryState
from episodes.terms import check_id
from episodes.times import time_or_now
from kg import Store
from kg.clock import Clock

__all__ = ["Ratings"]


class Ratings:
    """The ratings of one memory; ``clock`` gives the default times, ``memory_state`` the scene
    memory's state recorded when a rating session begins (see :mod:`episodes.snapshot`)."""

    def __init__(self, store: Store, *, clock: Clock, memory_state: MemoryState) -> None:
        self.store = store
        self.clock = clock
        self.memory_state = memory_state

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
        ``person`` must be (see :meth:`begin_session`)."""
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
            time=time_or_now(self.clock, time, "time"),
            sample=sample,
            question=question,
            replace=replace,
            session=given_in,
        )

    def begin_session(
        self,
        person: str,
        *,
        rated: Sequence[str] = (),
        begin: dt.datetime | str | None = None,
        episode_id: str | None = None,
    ) -> Episode:
        """Begin a rating session as a feedback episode and answer it: ``person`` (its
        agent) rates the data of the episodes ``rated``; ratings given with ``session=<its
        id>`` belong to it, and :meth:`episodes.EpisodeMemory.end` ends it. See
        :mod:`episodes.sessions`."""
        session_id = sessions.begin_session(
            self.store,
            person=person,
            rated=rated,
            begin=time_or_now(self.clock, begin, "begin"),
            episode_id=check_id(episode_id, "id") if episode_id is not None else None,
            memory_state=self.memory_state,
        )
        return lifecycle.get_episode(self.store, session_id)

    def of_session(self, session_id: str) -> list[Rating]:
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
