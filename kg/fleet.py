"""Opening a memory on a shared SPARQL server, as its writer or as a follower, and following
other robots' memories on the same server (a fleet view).

A fleet view reads every followed memory under its server graph names
(``https://w3id.org/engram/memory/<name>/graph/<g>``), beside the opened memory's own graphs
under Engram's names; each followed memory is polled by its own :class:`kg.follow.Follower`, so
its graph list and revision stay current.

>>> open_remote.__name__
'open_remote'
"""

import logging
from collections.abc import Sequence
from dataclasses import dataclass, field

from kg.follow import Follower
from kg.http import SparqlServer
from kg.lease import Lease
from kg.namespace import Namespace
from kg.profile import profile_named
from kg.remote import RemoteDataset
from kg.store import Store

__all__ = ["RemoteMemory", "open_remote"]

log = logging.getLogger(__name__)


@dataclass
class RemoteMemory:
    """A :class:`kg.Store` over a shared server, with its lease (writer) or follower."""

    store: Store
    dataset: RemoteDataset
    lease: Lease | None = None
    follower: Follower | None = None
    fleet: list[RemoteDataset] = field(default_factory=list)
    """Other robots' memories followed read-only (see the module's summary)."""
    fleet_followers: list[Follower] = field(default_factory=list)

    def fleet_graphs(self) -> list[str]:
        """The followed memories' graphs, by their names on the server."""
        return [g for dataset in self.fleet for g in dataset.graphs()]

    def close(self) -> None:
        """Stop following or give up the lease, then close the connections."""
        for follower in [*self.fleet_followers, self.follower]:
            if follower is not None:
                follower.stop()
        if self.lease is not None:
            self.lease.release()
        self.dataset.server.close()


def open_remote(
    url: str,
    memory: str,
    *,
    profile: str = "oxigraph",
    follow: bool = False,
    owner: str | None = None,
    lease_s: float = 15.0,
    poll_s: float = 0.1,
    timeout_s: float = 30.0,
    fleet: Sequence[str] = (),
) -> RemoteMemory:
    """Open memory ``memory`` on the SPARQL server at ``url``.

    As the writer (the default) it takes the memory's lease first and raises
    :class:`kg.errors.LeaseHeldError` if another Engram holds it; with ``follow`` it opens the
    memory read-only and follows the writer's revision. ``fleet`` names other memories on the
    server to follow read-only as well (not ``memory`` itself, no name twice). Raises
    ``ValueError`` for a bad memory name or profile, :class:`kg.errors.StoreUnavailableError`
    if the server does not answer.
    """
    namespace = Namespace(memory)
    others = [Namespace(name) for name in fleet]
    names = [memory, *fleet]
    if len(set(names)) != len(names):
        raise ValueError(
            f"fleet: got {list(fleet)!r}, expected other memories than {memory!r}, each once"
        )
    server = SparqlServer(url, profile_named(profile), timeout_s=timeout_s)
    followers: list[Follower] = []
    try:
        datasets = [RemoteDataset(server, other, read_only=True) for other in others]
        followers = [Follower(dataset, poll_s=poll_s) for dataset in datasets]
        dataset = RemoteDataset(server, namespace, read_only=follow)
        if follow:
            follower = Follower(dataset, poll_s=poll_s)
            for each in [follower, *followers]:
                each.start()
            return RemoteMemory(
                Store(backend=dataset),
                dataset,
                follower=follower,
                fleet=datasets,
                fleet_followers=followers,
            )
        lease = Lease(dataset, owner=owner, term_s=lease_s)
        lease.acquire()
        try:
            dataset.revision = dataset.read_revision()  # what committed before the lease
            for each in followers:
                each.start()
            return RemoteMemory(
                Store(backend=dataset),
                dataset,
                lease=lease,
                fleet=datasets,
                fleet_followers=followers,
            )
        except BaseException:
            lease.release()
            raise
    except BaseException:
        for each in followers:
            each.stop()
        server.close()
        raise
