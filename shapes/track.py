"""Tracking clusters across frames with stable ids (PITT's geometric tracker, quirks fixed).

PITT's rules: a detection joins the track whose smoothed centroid is nearest, if it lies within
``gate_m`` (20 cm); the track's centroid becomes ``0.6·old + 0.4·new``; a track that is not
matched for ``forget_after`` (3) consecutive frames is deleted; new tracks take the next id of a
global counter, so ids are never reused.

Fixed here (reference §4.16 #9): one update per frame over all detections; matching is global
nearest-first (all detection-track pairs within the gate, closest pair first, each track and
detection used once) instead of PITT's order-dependent greedy loop that dropped a detection whose
nearest track was taken; a detection whose nearest track is taken can still join another track
in its gate or start a new one; tracks age on empty frames too. A detection outside every gate
takes the nearest unmatched track of the same shape kind and size (within ``reid_gate_m`` and
``reid_size_m``): an object moved far in one step keeps its id.

>>> t = Tracker()
>>> t.update([np.array([0.0, 0.0, 0.0])])
[0]
>>> t.update([np.array([0.5, 0.0, 0.0]), np.array([0.01, 0.0, 0.0])])
[1, 0]
"""

from __future__ import annotations

import logging
from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np

from shapes.types import FloatArray

__all__ = ["Track", "Tracker"]

log = logging.getLogger(__name__)


@dataclass
class Track:
    """One tracked object: its id, smoothed centroid, and how often it was seen and missed."""

    id: int
    centroid: FloatArray
    hits: int = 1
    missed: int = 0
    signature: tuple[str, float] | None = None


@dataclass
class Tracker:
    """Gated nearest-centroid tracker with exponential smoothing and deletion after misses."""

    gate_m: float = 0.20
    forget_after: int = 3
    weight_old: float = 0.6
    weight_new: float = 0.4
    tracks: dict[int, Track] = field(default_factory=dict)
    next_id: int = 0
    deleted: list[int] = field(default_factory=list)
    reid_gate_m: float = 1.0
    reid_size_m: float = 0.01

    def __post_init__(self) -> None:
        if self.gate_m <= 0 or self.forget_after < 1 or self.weight_old < 0 or self.weight_new <= 0:
            raise ValueError(
                "Tracker: expected gate_m > 0, forget_after >= 1, weight_old >= 0 and "
                f"weight_new > 0, got {self.gate_m}, {self.forget_after}, {self.weight_old}, "
                f"{self.weight_new}"
            )

    def update(
        self,
        centroids: Sequence[FloatArray],
        signatures: Sequence[tuple[str, float] | None] | None = None,
    ) -> list[int]:
        """Match this frame's cluster centroids to tracks; return one track id per centroid.

        ``signatures`` (the shape kind and size of each detection): a detection left without a
        track in the gate takes the nearest unmatched track within ``reid_gate_m`` that has
        the same kind and a size within ``reid_size_m``, so an object moved far keeps its id.

        Tracks not matched this frame age by one; those missed ``forget_after`` times in a row
        are deleted (their ids are listed in ``self.deleted`` until the next update).
        """
        self.deleted = []
        ids = list(self.tracks)
        assigned: list[int | None] = [None] * len(centroids)
        if ids and len(centroids):
            cur = np.array([self.tracks[i].centroid for i in ids])
            det = np.asarray(centroids, dtype=np.float64).reshape(len(centroids), 3)
            dist = np.linalg.norm(det[:, None, :] - cur[None, :, :], axis=2)
            used_tracks: set[int] = set()
            for flat in np.argsort(dist, axis=None, kind="stable"):
                d_i, t_i = divmod(int(flat), len(ids))
                if dist[d_i, t_i] > self.gate_m:
                    break
                if assigned[d_i] is not None or t_i in used_tracks:
                    continue
                assigned[d_i] = ids[t_i]
                used_tracks.add(t_i)
        sigs: list[tuple[str, float] | None] = (
            list(signatures) if signatures is not None else [None] * len(centroids)
        )
        self._reidentify(centroids, sigs, assigned, ids)
        total = self.weight_old + self.weight_new
        for i, c in enumerate(centroids):
            track_id = assigned[i]
            if track_id is None:
                track_id = self.next_id
                self.next_id += 1
                self.tracks[track_id] = Track(
                    track_id, np.asarray(c, dtype=np.float64).copy(), signature=sigs[i]
                )
                assigned[i] = track_id
                log.debug("new track %d at %s", track_id, c)
                continue
            tr = self.tracks[track_id]
            tr.centroid = (self.weight_old * tr.centroid + self.weight_new * np.asarray(c)) / total
            tr.hits += 1
            tr.missed = 0
            if sigs[i] is not None:
                tr.signature = sigs[i]
        seen = set(assigned)
        for track_id in list(self.tracks):
            if track_id in seen:
                continue
            tr = self.tracks[track_id]
            tr.missed += 1
            if tr.missed >= self.forget_after:
                del self.tracks[track_id]
                self.deleted.append(track_id)
                log.debug("track %d deleted after %d misses", track_id, tr.missed)
        return [int(a) for a in assigned if a is not None]

    def _reidentify(
        self,
        centroids: Sequence[FloatArray],
        sigs: list[tuple[str, float] | None],
        assigned: list[int | None],
        ids: list[int],
    ) -> None:
        """Give unassigned detections the nearest free track of the same shape and size."""
        taken = {a for a in assigned if a is not None}
        for i, c in enumerate(centroids):
            sig = sigs[i]
            if assigned[i] is not None or sig is None:
                continue
            best, best_d = None, self.reid_gate_m
            for track_id in ids:
                tr = self.tracks[track_id]
                if track_id in taken or tr.signature is None or tr.signature[0] != sig[0]:
                    continue
                if abs(tr.signature[1] - sig[1]) > self.reid_size_m:
                    continue
                d = float(np.linalg.norm(np.asarray(c) - tr.centroid))
                if d < best_d:
                    best, best_d = track_id, d
            if best is not None:
                assigned[i] = best
                taken.add(best)
                self.tracks[best].centroid = np.asarray(c, dtype=np.float64).copy()
                log.debug("track %d re-identified %.2f m away", best, best_d)
