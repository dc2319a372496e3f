"""One writer per memory: the writer's lease on a shared SPARQL server.

The server detects no write-write conflict (a guarded update answers 204 whether it applied or
not, and two guarded updates can both apply), so a lease is taken in two steps:

1. a guarded update adds this Engram's claim (a fresh IRI, its owner's name and an expiry) if no
   other claim runs past now, dropping expired claims;
2. the claims are read back: the lease is held only if this claim is the one running claim.

Two Engrams racing can both add a claim, but then each reads back the other's and gives up; a
claim cannot be removed by a rival (only expired claims are dropped), so two never both see
themselves alone. The holder renews before a third of the term has passed, from a background
thread that also settles the store after a failed write (:meth:`kg.remote.RemoteDataset.settle`).

>>> Lease.__name__
'Lease'
"""

import datetime as dt
import logging
import os
import socket
import threading
import uuid

from pyoxigraph import Literal, NamedNode

import sparql
from kg.clock import Clock, utc_now
from kg.errors import LeaseHeldError, StoreError, StoreUnavailableError
from kg.remote import RemoteDataset
from kg.sparql_text import bind_values
from ontologies.vocab import XSD_DATETIME

__all__ = ["Lease", "default_owner"]

log = logging.getLogger(__name__)


def default_owner() -> str:
    """``host:pid``: who holds a lease, as an operator reads it."""
    return f"{socket.gethostname()}:{os.getpid()}"


def _time(value: dt.datetime) -> Literal:
    return Literal(value.isoformat(), datatype=XSD_DATETIME)


class Lease:
    """The writer's lease of ``dataset``'s memory, taken by :meth:`acquire`.

    ``term_s`` is how long a claim runs without renewal. Installs itself as the dataset's write
    guard: a write while the lease is not held raises.
    """

    def __init__(
        self,
        dataset: RemoteDataset,
        *,
        owner: str | None = None,
        term_s: float = 15.0,
        clock: Clock = utc_now,
    ) -> None:
        if not term_s > 0:
            raise ValueError(f"lease term_s: got {term_s!r}, expected a positive number of seconds")
        self.dataset = dataset
        self.owner = owner or default_owner()
        self.term_s = term_s
        self.claim = NamedNode(f"{dataset.namespace.prefix}lease/{uuid.uuid4().hex}")
        self.expires: dt.datetime | None = None
        self._clock = clock
        self._stop = threading.Event()
        self._renewer: threading.Thread | None = None

    def _bindings(self, now: dt.datetime) -> dict[str, NamedNode | Literal]:
        ns = self.dataset.namespace
        until = now + dt.timedelta(seconds=self.term_s)
        return {
            "control": ns.control,
            "memory": ns.node,
            "claim": self.claim,
            "owner": Literal(self.owner),
            "now": _time(now),
            "until": _time(until),
        }

    def acquire(self) -> None:
        """Take the lease, or raise :class:`LeaseHeldError` naming who holds it until when.

        On success a background thread renews it until :meth:`release`.
        """
        self._renew()
        self._stop.clear()
        self._renewer = threading.Thread(
            target=self._keep, name=f"engram-lease-{self.dataset.namespace.name}", daemon=True
        )
        self._renewer.start()
        self.dataset.guard = self.check
        log.info("took the writer's lease of memory %s", self.dataset.namespace.name)

    def _renew(self) -> None:
        now = self._clock()
        bindings = self._bindings(now)
        self.dataset.server.update(bind_values(sparql.load("lease_take"), bindings))
        claims = self._claims(now)
        others = [(owner, until) for claim, owner, until in claims if claim != self.claim]
        if others or not any(claim == self.claim for claim, _, _ in claims):
            self._give_up()
            self.expires = None
            owner, until = others[0] if others else ("another Engram", now)
            raise LeaseHeldError(
                f"memory {self.dataset.namespace.name!r} on {self.dataset.server.url} is written "
                f"by {owner} until {until.isoformat()}; one Engram writes a memory: stop it, "
                "wait for its lease to expire, or open this memory as a follower"
            )
        self.expires = dt.datetime.fromisoformat(str(bindings["until"].value))

    def _claims(self, now: dt.datetime) -> list[tuple[NamedNode, str, dt.datetime]]:
        ns = self.dataset.namespace
        text = bind_values(sparql.load("lease_holders"), {"control": ns.control, "memory": ns.node})
        rows = self.dataset.select_raw(
            text, default_graphs=[ns.control.value], named_graphs=[ns.control.value]
        )
        claims = []
        for row in rows:
            expires = dt.datetime.fromisoformat(row["expires"].value)
            if expires > now:
                owner = row["owner"].value if "owner" in row else row["claim"].value
                claims.append((row["claim"], owner, expires))
        return claims

    def _give_up(self) -> None:
        ns = self.dataset.namespace
        bindings = {"control": ns.control, "memory": ns.node, "claim": self.claim}
        try:
            self.dataset.server.update(bind_values(sparql.load("lease_release"), bindings))
        except StoreError as error:  # it expires on its own
            log.warning("could not withdraw the lease claim of %s: %s", ns.name, error)

    def check(self) -> None:
        """Raise unless the lease is held for a while yet; renew it first when it runs low."""
        if self.expires is None:
            raise LeaseHeldError(
                f"this Engram does not hold the writer's lease of memory "
                f"{self.dataset.namespace.name!r}; it may not write"
            )
        left = (self.expires - self._clock()).total_seconds()
        if left < self.term_s / 3:
            self._renew()

    def _keep(self) -> None:
        while not self._stop.wait(self.term_s / 3):
            try:
                self._renew()
                self.dataset.settle()
            except LeaseHeldError as error:
                log.error("lost the writer's lease: %s", error)
                return
            except StoreUnavailableError as error:
                log.warning("cannot renew the writer's lease yet: %s", error)

    def release(self) -> None:
        """Stop renewing and withdraw the claim, so another Engram can write at once."""
        self._stop.set()
        if self._renewer is not None:
            self._renewer.join()
        if self.expires is not None:
            self._give_up()
            self.expires = None
            log.info("gave up the writer's lease of memory %s", self.dataset.namespace.name)
