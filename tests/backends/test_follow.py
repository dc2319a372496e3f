"""A follower reads what the writer's journal names, and rebuilds when the journal was trimmed."""

import pytest
from pyoxigraph import Literal

from kg.fleet import open_remote
from kg.follow import Follower
from kg.http import SparqlServer
from kg.namespace import Namespace
from kg.profile import profile_named
from kg.remote import RemoteDataset
from ontologies.vocab import MEMORY, RDFS_LABEL, TRASH, engram

pytestmark = pytest.mark.slow


def test_a_follower_is_told_exactly_the_subjects_the_writer_touched(
    sparql_server: tuple[str, str], memory_name: str
) -> None:
    url, profile = sparql_server
    writer = open_remote(url, memory_name, profile=profile)
    server = SparqlServer(url, profile_named(profile))
    try:
        reader = RemoteDataset(server, Namespace(memory_name), read_only=True)
        follower = Follower(reader)
        assert follower.catch_up() is None  # nothing new
        with writer.store.transaction() as tx:
            tx.insert(engram("Scene-1"), RDFS_LABEL, Literal("one"), MEMORY)
        with writer.store.transaction() as tx:
            tx.insert(engram("Scene-2"), RDFS_LABEL, Literal("two"), TRASH)
        change = follower.catch_up()
        assert change is not None and change.revision == writer.dataset.revision
        assert change.touched == {engram("Scene-1"), engram("Scene-2")}
        with writer.store.transaction() as tx:
            tx.clear_graph(TRASH)
        change = follower.catch_up()
        assert change is not None and change.touched is None  # a cleared graph: rebuild
    finally:
        server.close()
        writer.close()


def test_a_follower_further_behind_than_the_journal_rebuilds(
    sparql_server: tuple[str, str], memory_name: str
) -> None:
    url, profile = sparql_server
    writer = open_remote(url, memory_name, profile=profile)
    writer.dataset.journal_length = 2
    server = SparqlServer(url, profile_named(profile))
    try:
        reader = RemoteDataset(server, Namespace(memory_name), read_only=True)
        follower = Follower(reader)
        for n in range(4):
            with writer.store.transaction() as tx:
                tx.insert(engram(f"Scene-{n}"), RDFS_LABEL, Literal(str(n)), MEMORY)
        change = follower.catch_up()
        assert change is not None and change.touched is None and change.revision == 4
        with writer.store.transaction() as tx:
            tx.insert(engram("Scene-9"), RDFS_LABEL, Literal("9"), MEMORY)
        assert follower.catch_up().touched == {engram("Scene-9")}  # type: ignore[union-attr]
    finally:
        server.close()
        writer.close()
