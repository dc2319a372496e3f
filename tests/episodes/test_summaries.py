"""Summaries read from the store's indexes (episodes/summaries.py) equal the rows of the
``episodes_summary`` query they replace, through arguments added and retracted after the fact."""

import datetime as dt

from hypothesis import given, settings
from hypothesis import strategies as st
from pyoxigraph import NamedNode

from episodes import ArgumentSpec, EpisodeMemory, lifecycle
from episodes.cues import _summary
from episodes.summaries import read_summaries
from episodes.terms import episode_iri
from kg import Store
from kg.errors import EngramError

NOW = dt.datetime(2026, 2, 26, 10, 0, tzinfo=dt.UTC)
NAMES = ("HyungJin", "ball", "https://example.org/robot", "Maxime")

episodes = st.lists(
    st.tuples(
        st.sampled_from(("babbling", "point")),
        st.none() | st.sampled_from(("motor", "social")),
        st.lists(
            st.tuples(st.sampled_from(("agent", "object", "recipient")), st.sampled_from(NAMES)),
            unique=True,
            max_size=3,
        ),
        st.booleans(),  # ended
        st.lists(
            st.tuples(
                st.sampled_from(("agent", "object", "recipient")),
                st.sampled_from(NAMES),
                st.booleans(),
            ),
            max_size=3,
        ),  # later: add / retract
    ),
    max_size=6,
)


@settings(max_examples=40, deadline=None)
@given(episodes)
def test_summaries_equal_the_summary_query(specs: list) -> None:  # type: ignore[type-arg]
    memory = EpisodeMemory(Store(), clock=lambda: NOW)
    begin = dt.datetime(2026, 1, 1, tzinfo=dt.UTC)
    for k, (activity, kind, arguments, ended, later) in enumerate(specs):
        lifecycle.begin_episode(
            memory.store,
            activity=activity,
            activity_type=kind,
            episode_id=f"e{k}",
            arguments=[ArgumentSpec(r, v) for r, v in arguments],
            snapshots=False,
            begin=begin + dt.timedelta(hours=k),
            end=begin + dt.timedelta(hours=k, minutes=5) if ended else None,
        )
        for role, value, add in later:
            try:
                if add:
                    memory.add_argument(f"e{k}", role=role, value=value)
                else:
                    memory.remove_argument(f"e{k}", role=role, value=value)
            except EngramError:  # already there / not there: the memory refuses, nothing changes
                pass
    asked = [episode_iri(f"e{k}") for k in range(len(specs) + 1)]  # the last is no episode
    asked.append(NamedNode("https://example.org/not-an-episode"))
    expected = [
        _summary(row) for e in asked for row in memory.store.select("episodes_summary", episode=e)
    ]
    assert read_summaries(memory.store, asked) == expected
