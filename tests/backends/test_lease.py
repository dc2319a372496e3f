"""One writer per memory: the lease on a real SPARQL server."""

import datetime as dt

import pytest
from pyoxigraph import Literal

from kg.errors import LeaseHeldError
from kg.fleet import open_remote
from kg.http import SparqlServer
from kg.lease import Lease
from kg.namespace import Namespace
from kg.profile import profile_named
from kg.remote import RemoteDataset
from ontologies.vocab import MEMORY, RDFS_LABEL, engram

pytestmark = pytest.mark.slow


def test_a_second_writer_gets_a_clear_error_naming_the_holder_and_does_not_start(
    sparql_server: tuple[str, str], memory_name: str
) -> None:
    url, profile = sparql_server
    first = open_remote(url, memory_name, profile=profile, owner="robot-a-main")
    try:
        with pytest.raises(LeaseHeldError, match=r"written by robot-a-main until .*follower"):
            open_remote(url, memory_name, profile=profile, owner="intruder")
        with first.store.transaction() as tx:  # the holder still writes
            tx.insert(engram("x"), RDFS_LABEL, Literal("x"), MEMORY)
    finally:
        first.close()
    second = open_remote(url, memory_name, profile=profile, owner="next")  # released: free
    second.close()


def test_an_expired_lease_is_taken_over_and_its_old_holder_may_no_longer_write(
    sparql_server: tuple[str, str], memory_name: str
) -> None:
    url, profile = sparql_server
    now = [dt.datetime(2030, 1, 1, tzinfo=dt.UTC)]
    server = SparqlServer(url, profile_named(profile))
    old = RemoteDataset(server, Namespace(memory_name))
    lease = Lease(old, owner="old", term_s=60, clock=lambda: now[0])
    lease._renew()  # taken at the fake time, not renewed by a thread
    old.guard = lease.check
    now[0] += dt.timedelta(minutes=5)
    newcomer = Lease(
        RemoteDataset(server, Namespace(memory_name)), owner="new", term_s=60, clock=lambda: now[0]
    )
    newcomer._renew()
    with pytest.raises(LeaseHeldError, match="written by new"):
        old.commit([], [], [])
    server.close()


def test_racing_writers_never_both_hold_the_lease(
    sparql_server: tuple[str, str], memory_name: str
) -> None:
    import threading

    url, profile = sparql_server
    server = SparqlServer(url, profile_named(profile))
    leases = [Lease(RemoteDataset(server, Namespace(memory_name)), owner=f"w{i}") for i in range(6)]
    held, barrier = [], threading.Barrier(len(leases))

    def take(lease: Lease) -> None:
        barrier.wait()
        try:
            lease._renew()
            held.append(lease.owner)
        except LeaseHeldError:
            pass

    threads = [threading.Thread(target=take, args=(lease,)) for lease in leases]
    for thread in threads:
        thread.start()
    for thread in threads:
        thread.join()
    assert len(held) <= 1
    server.close()
