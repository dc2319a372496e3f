"""Pending augmentation work served to augmenter processes: claim, heartbeat, complete.

An augmenter asks for an ended episode of an activity that lacks its augmentation (fewer than
``versions`` runs); the claim starts a run for it (``producer`` = the worker) and leases the
episode for ``lease_s`` seconds, so no other worker gets it. The worker sends heartbeats to keep
the lease, posts its derived samples to the run, then completes the claim, which ends the run.
A lease that runs out (the worker died) discards its unfinished run, triples and file, so the
episode lacks the augmentation again and the next claim gets it. A claim may wait up to
``wait_s`` for work to appear (long-poll).

Leases live in the serving process: after a restart, unfinished runs of lost leases stay as
runs without an end (visible in ``runs``), and the episodes they belong to are not offered
again until a run of them ends or is deleted.
"""

import datetime as dt
import secrets
import threading
import time
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any, Protocol

from episodes.errors import InvalidInputError, NotFoundError
from episodes.model import AugmentationRun
from episodes.terms import check_name

__all__ = ["AugmentationQueue", "Claim"]

MAX_LEASE_S = 3600.0
MAX_WAIT_S = 60.0
POLL_S = 0.1


class _Runs(Protocol):
    """What the queue needs of :class:`episodes.runs.AugmentationRuns`."""

    clock: Callable[[], dt.datetime]

    def lacking(
        self, activity: str, augmentation_name: str, *, versions: int = 1
    ) -> list[tuple[Any, int]]: ...

    def start(self, episode_id: str, *, name: str, producer: str) -> AugmentationRun: ...

    def end(self, episode_id: str, run_id: str) -> AugmentationRun: ...

    def discard(self, episode_id: str, run_id: str) -> None: ...


@dataclass(frozen=True)
class Claim:
    """Work handed to a worker: the episode, the run started for it, and its lease."""

    token: str
    augmentation: str
    episode_id: str
    run: AugmentationRun
    worker: str
    expires: dt.datetime


def _number(value: object, field: str, low: float, high: float) -> float:
    if isinstance(value, bool) or not isinstance(value, int | float) or not low < value <= high:
        raise InvalidInputError(
            field, value, f"a number of seconds above {low:g}, at most {high:g}"
        )
    return float(value)


class AugmentationQueue:
    """The leases over one memory's augmentation runs (``runs``), thread-safe.

    ``monotonic`` is the clock of the leases (injectable for tests).
    """

    def __init__(self, runs: _Runs, *, monotonic: Callable[[], float] = time.monotonic):
        self.runs = runs
        self._monotonic = monotonic
        self._lock = threading.Lock()
        self._leases: dict[str, tuple[Claim, float]] = {}

    def claim(
        self,
        augmentation: str,
        *,
        worker: str,
        activity: str,
        versions: int = 1,
        lease_s: float = 60.0,
        wait_s: float = 0.0,
    ) -> Claim | None:
        """Claim an ended episode of ``activity`` lacking ``augmentation``; ``None`` when there
        is none after waiting ``wait_s``. Raises :class:`InvalidInputError` for bad values."""
        augmentation = check_name(augmentation, "augmentation")
        worker = check_name(worker, "worker")
        activity = check_name(activity, "activity")
        lease = _number(lease_s, "lease_s", 0, MAX_LEASE_S)
        wait = _number(wait_s, "wait_s", -1e-9, MAX_WAIT_S) if wait_s else 0.0
        deadline = self._monotonic() + wait
        while True:
            found = self._try_claim(augmentation, worker, activity, versions, lease)
            if found is not None or self._monotonic() >= deadline:
                return found
            time.sleep(min(POLL_S, max(0.0, deadline - self._monotonic())))

    def _try_claim(
        self, augmentation: str, worker: str, activity: str, versions: int, lease_s: float
    ) -> Claim | None:
        with self._lock:
            self._expire()
            leased = {
                c.episode_id for c, _ in self._leases.values() if c.augmentation == augmentation
            }
            for summary, _ in self.runs.lacking(activity, augmentation, versions=versions):
                if summary.end is None or summary.id in leased:
                    continue
                run = self.runs.start(summary.id, name=augmentation, producer=worker)
                token = secrets.token_urlsafe(16)
                claim = Claim(token, augmentation, summary.id, run, worker, self._expiry(lease_s))
                self._leases[token] = (claim, self._monotonic() + lease_s)
                return claim
        return None

    def _expiry(self, lease_s: float) -> dt.datetime:
        return self.runs.clock() + dt.timedelta(seconds=lease_s)

    def _expire(self) -> None:
        now = self._monotonic()
        for token, (claim, until) in list(self._leases.items()):
            if until <= now:
                del self._leases[token]
                self.runs.discard(claim.episode_id, claim.run.id)

    def _held(self, token: str) -> tuple[Claim, float]:
        self._expire()
        held = self._leases.get(token)
        if held is None:
            raise NotFoundError(f"claim: no lease {token!r} (completed, or expired and discarded)")
        return held

    def heartbeat(self, token: str, *, lease_s: float = 60.0) -> Claim:
        """Keep a lease for ``lease_s`` more seconds; raises :class:`NotFoundError` if it is
        gone (its run was discarded: start over with a new claim)."""
        lease = _number(lease_s, "lease_s", 0, MAX_LEASE_S)
        with self._lock:
            claim, _ = self._held(token)
            renewed = Claim(
                claim.token,
                claim.augmentation,
                claim.episode_id,
                claim.run,
                claim.worker,
                self._expiry(lease),
            )
            self._leases[token] = (renewed, self._monotonic() + lease)
            return renewed

    def complete(self, token: str) -> AugmentationRun:
        """End the claimed run and release the lease; returns the ended run."""
        with self._lock:
            claim, _ = self._held(token)
            del self._leases[token]
        return self.runs.end(claim.episode_id, claim.run.id)
