"""Tracking clusters across frames with stable ids (PITT's geometric tracker, quirks fixed).

PITT's rules: a detection joins the track whose smoothed centroid is nearest, if it lies within
``gate_m`` (20 cm); the track's centroid becomes ``0.6·old + 0.4·new``; a track that is not
matched for ``forget_after`` (3) consecutive frames is deleted; new tracks take the next id of a
global counter, so ids are never reused.

Fixed here (reference §4.16 #9): one update per frame over all detections; matching is global
nearest-first (all detection-track pairs within the gate, closest pair first, each track and
detection used once) instead of PITT's order-dependent greedy loop that dropped a detection whose
nearest track was taken; a detection whose nearest track is taken can still join another track
in its gate or start a new one; tracks age on empty frames too.

Added:

- **Extent.** A detection may carry its points' bounding box in the gravity frame. A track keeps
  the smoothed box of its object (the union of the boxes of the detections that got its id in a
  frame). A detection and a track with boxes match only if the boxes, each grown by
  ``jitter_m``, overlap: a small part of one object whose centroid lies 17 cm from another
  track's no longer takes that track's id.
- **Parts of one object.** Segmentation of a real scan cuts a thin or far object (a chair's
  tubes, the strip at the edge of a box) into pieces that change from frame to frame. A
  detection left without a track whose box lies, for at least ``part_share`` of its volume,
  inside the box of a larger track grown by ``jitter_m`` is a part of that object and gets its
  id (not all of it: where the image's edge or an occluder cuts a large object, its box ends
  wherever the cut falls in that frame, and a piece of its edge may stick out of the box the
  object had in the frame before by more than the jitter); several detections of
  one frame may therefore share an id (:meth:`Tracker.update` says which, in ``parts``). Within
  a frame, larger detections are placed first, so a part seen in the first frame joins the
  object it belongs to. A detection whose box is a point (a support given by its centre) has no
  extent: it is matched by its centroid alone and is never a part.
- **Re-identification.** A detection outside every gate takes the nearest unmatched track of
  the same shape kind and size (within ``reid_gate_m`` and ``reid_size_m``): an object moved far
  in one step keeps its id.

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

from shapes.arrays import column_max, column_min
from shapes.types import FloatArray

__all__ = ["Box", "Track", "Tracker", "box_of"]

log = logging.getLogger(__name__)

Box = tuple[FloatArray, FloatArray]
"""An axis-aligned box in the gravity frame: its lower and upper corners, in metres."""


def box_of(points: FloatArray) -> Box:
    """The bounding box of an (n, 3) array of points (n >= 1).

    >>> lo, hi = box_of(np.array([[0.0, 1.0, 2.0], [1.0, 0.0, 3.0]]))
    >>> lo.tolist(), hi.tolist()
    ([0.0, 0.0, 2.0], [1.0, 1.0, 3.0])
    """
    pts = np.asarray(points, dtype=np.float64).reshape(-1, 3)
    return column_min(pts), column_max(pts)


def _extent(box: Box | None) -> Box | None:
    """The box as floats, or None when it is missing or a point (no extent)."""
    if box is None:
        return None
    lo, hi = np.asarray(box[0], dtype=np.float64), np.asarray(box[1], dtype=np.float64)
    return (lo, hi) if bool(np.any(hi - lo > 0.0)) else None


def _size(box: Box) -> float:
    return float(np.linalg.norm(box[1] - box[0]))


def _overlap(a: Box, b: Box, grow_m: float) -> bool:
    """The boxes overlap once each is grown by ``grow_m`` on every side."""
    return bool(np.all(a[0] - grow_m <= b[1] + grow_m) and np.all(b[0] - grow_m <= a[1] + grow_m))


def _share_inside(inner: Box, outer: Box, grow_m: float) -> float:
    """The share of ``inner``'s volume that lies inside ``outer`` grown by ``grow_m`` on every
    side (along an axis where ``inner`` is flat, 1 if it lies within the grown range, else 0).

    >>> _share_inside((np.zeros(3), np.array([0.1, 0.2, 0.1])), (np.zeros(3), np.full(3, 0.1)), 0.0)
    0.5
    """
    lo, hi = np.maximum(inner[0], outer[0] - grow_m), np.minimum(inner[1], outer[1] + grow_m)
    length = inner[1] - inner[0]
    flat = length <= 0.0
    covered = np.where(flat, (hi >= lo).astype(np.float64), np.clip(hi - lo, 0.0, None))
    return float(np.prod(covered / np.where(flat, 1.0, length)))


@dataclass
class Track:
    """One tracked object: its id, smoothed centroid and box, how often seen and missed."""

    id: int
    centroid: FloatArray
    hits: int = 1
    missed: int = 0
    signature: tuple[str, float] | None = None
    box: Box | None = None
    """The smoothed bounding box of the object's detections (None when they had no extent)."""


@dataclass
class Tracker:
    """Gated nearest-centroid tracker with extents, exponential smoothing and deletion after
    misses (see the module docstring)."""

    gate_m: float = 0.20
    forget_after: int = 3
    weight_old: float = 0.6
    weight_new: float = 0.4
    tracks: dict[int, Track] = field(default_factory=dict)
    next_id: int = 0
    deleted: list[int] = field(default_factory=list)
    reid_gate_m: float = 1.0
    reid_size_m: float = 0.01
    jitter_m: float = 0.04
    """How far a static object's box edges may move between frames of a real scan."""
    part_share: float = 0.5
    """How much of a detection's box must lie inside a larger track's grown box for it to be a
    part of that object."""
    parts: list[bool] = field(default_factory=list)
    """For each detection of the last update: it was taken as a part of a larger one."""

    def __post_init__(self) -> None:
        if (
            self.gate_m <= 0
            or self.forget_after < 1
            or self.weight_old < 0
            or self.weight_new <= 0
            or self.jitter_m < 0
            or not 0 < self.part_share <= 1
        ):
            raise ValueError(
                "Tracker: expected gate_m > 0, forget_after >= 1, weight_old >= 0, "
                "weight_new > 0, jitter_m >= 0 and 0 < part_share <= 1, got "
                f"{self.gate_m}, {self.forget_after}, {self.weight_old}, {self.weight_new}, "
                f"{self.jitter_m}, {self.part_share}"
            )

    def update(
        self,
        centroids: Sequence[FloatArray],
        signatures: Sequence[tuple[str, float] | None] | None = None,
        boxes: Sequence[Box | None] | None = None,
    ) -> list[int]:
        """Match this frame's cluster centroids to tracks; return one track id per centroid.

        ``signatures`` (the shape kind and size of each detection): a detection left without a
        track in the gate takes the nearest unmatched track within ``reid_gate_m`` that has
        the same kind and a size within ``reid_size_m``, so an object moved far keeps its id.
        ``boxes`` (each detection's bounding box, :func:`box_of`): matches need overlapping
        boxes, and a detection mostly inside a larger object's box is a part of it and shares its id
        (``self.parts`` marks those detections).

        Tracks not matched this frame age by one; those missed ``forget_after`` times in a row
        are deleted (their ids are listed in ``self.deleted`` until the next update).

        Raises ValueError when ``signatures`` or ``boxes`` is not one per centroid.
        """
        n = len(centroids)
        sigs: list[tuple[str, float] | None] = (
            list(signatures) if signatures is not None else [None] * n
        )
        extents = [_extent(b) for b in (boxes if boxes is not None else [None] * n)]
        if len(sigs) != n or len(extents) != n:
            raise ValueError(
                f"Tracker.update: expected one signature and one box per centroid ({n}), got "
                f"{len(sigs)} and {len(extents)}"
            )
        self.deleted = []
        self.parts = [False] * n
        ids = list(self.tracks)
        assigned: list[int | None] = [None] * n
        if ids and n:
            cur = np.array([self.tracks[i].centroid for i in ids])
            det = np.asarray(centroids, dtype=np.float64).reshape(n, 3)
            dist = np.linalg.norm(det[:, None, :] - cur[None, :, :], axis=2)
            used_tracks: set[int] = set()
            for flat in np.argsort(dist, axis=None, kind="stable"):
                d_i, t_i = divmod(int(flat), len(ids))
                if dist[d_i, t_i] > self.gate_m:
                    break
                if assigned[d_i] is not None or t_i in used_tracks:
                    continue
                box, track_box = extents[d_i], self.tracks[ids[t_i]].box
                if box is None or track_box is None or _overlap(box, track_box, self.jitter_m):
                    assigned[d_i] = ids[t_i]
                    used_tracks.add(t_i)
        self._join_parts(extents, assigned)
        self._reidentify(centroids, sigs, assigned, ids)
        self._start_tracks(centroids, sigs, extents, assigned)
        self._smooth(centroids, sigs, extents, assigned)
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

    def _host(self, box: Box, hosts: Sequence[int]) -> int | None:
        """The smallest track among ``hosts`` larger than ``box`` whose grown box holds at least
        ``part_share`` of it."""
        best, best_size = None, np.inf
        for track_id in hosts:
            host = self.tracks[track_id].box
            if host is None or _size(host) <= _size(box):
                continue
            if _share_inside(box, host, self.jitter_m) < self.part_share:
                continue
            if _size(host) < best_size:
                best, best_size = track_id, _size(host)
        return best

    def _join_parts(self, extents: list[Box | None], assigned: list[int | None]) -> None:
        """Give a detection without a track the id of an existing object it is a part of."""
        existing = list(self.tracks)
        for i, box in enumerate(extents):
            if assigned[i] is not None or box is None:
                continue
            host = self._host(box, existing)
            if host is not None:
                assigned[i] = host
                self.parts[i] = True
                log.debug("detection %d is a part of track %d", i, host)

    def _start_tracks(
        self,
        centroids: Sequence[FloatArray],
        sigs: list[tuple[str, float] | None],
        extents: list[Box | None],
        assigned: list[int | None],
    ) -> None:
        """New tracks for the detections still without one, largest first; a detection inside
        a larger one started this frame is a part of it."""

        def size(i: int) -> float:
            box = extents[i]
            return 0.0 if box is None else _size(box)

        fresh: list[int] = []
        for i in sorted((i for i, a in enumerate(assigned) if a is None), key=size, reverse=True):
            box = extents[i]
            host = None if box is None else self._host(box, fresh)
            if host is not None:
                assigned[i] = host
                self.parts[i] = True
                continue
            track_id = self.next_id
            self.next_id += 1
            self.tracks[track_id] = Track(
                track_id,
                np.asarray(centroids[i], dtype=np.float64).copy(),
                hits=0,
                signature=sigs[i],
                box=box,
            )
            fresh.append(track_id)
            assigned[i] = track_id
            log.debug("new track %d at %s", track_id, centroids[i])

    def _smooth(
        self,
        centroids: Sequence[FloatArray],
        sigs: list[tuple[str, float] | None],
        extents: list[Box | None],
        assigned: list[int | None],
    ) -> None:
        """Fold this frame's detections into their tracks: the centroid of the one matched
        detection (not of parts), the union of the boxes of all detections with the id."""
        total = self.weight_old + self.weight_new
        boxes: dict[int, Box] = {}
        for i, track_id in enumerate(assigned):
            assert track_id is not None
            box = extents[i]
            if box is not None:
                prev = boxes.get(track_id)
                union = (
                    box
                    if prev is None
                    else (np.minimum(prev[0], box[0]), np.maximum(prev[1], box[1]))
                )
                boxes[track_id] = union
            tr = self.tracks[track_id]
            tr.missed = 0
            if self.parts[i]:
                continue
            if tr.hits == 0:  # started this frame
                continue
            c = np.asarray(centroids[i], dtype=np.float64)
            tr.centroid = (self.weight_old * tr.centroid + self.weight_new * c) / total
            tr.hits += 1
            if sigs[i] is not None:
                tr.signature = sigs[i]
        for track_id, box in boxes.items():
            tr = self.tracks[track_id]
            if tr.box is None or tr.hits == 0:
                tr.box = box
            else:
                tr.box = (
                    (self.weight_old * tr.box[0] + self.weight_new * box[0]) / total,
                    (self.weight_old * tr.box[1] + self.weight_new * box[1]) / total,
                )
        for track_id in set(assigned):
            assert track_id is not None
            tr = self.tracks[track_id]
            tr.hits = max(tr.hits, 1)

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
                self.tracks[best].box = None  # the box it had is where it was
                log.debug("track %d re-identified %.2f m away", best, best_d)
