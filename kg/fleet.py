"""Opening a memory on a shared SPARQL server, as its writer or as a follower.

>>> open_remote.__name__
'open_remote'
"""

import logging
from dataclasses import dataclass

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

    def close(self) -> None:
        """Stop following or give up the lease, then close the connections."""
        if self.follower is not None:
            self.follower.stop()
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
) -> RemoteMemory:
    """Open memory ``memory`` on the SPARQL server at ``url``.

    As the writer (the default) it takes the memory's lease first and raises
    :class:`kg.errors.LeaseHeldError` if another Engram holds it; with ``follow`` it opens the
    memory read-only and follows the writer's revision. Raises ``ValueError`` for a bad memory
    name or profile, :class:`kg.errors.StoreUnavailableError` if the server does not answer.
    """
    namespace = Namespace(memory)
    server = SparqlServer(url, profile_named(profile), timeout_s=timeout_s)
    try:
        dataset = RemoteDataset(server, namespace, read_only=follow)
        if follow:
            follower = Follower(dataset, poll_s=poll_s)
            follower.start()
            return RemoteMemory(Store(backend=dataset), dataset, follower=follower)
        lease = Lease(dataset, owner=owner, term_s=lease_s)
        lease.acquire()
        try:
            dataset.revision = dataset.read_revision()  # what committed before the lease
            return RemoteMemory(Store(backend=dataset), dataset, lease=lease)
        except BaseException:
            lease.release()
            raise
    except BaseException:
        server.close()
        raise
