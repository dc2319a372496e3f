"""Averaging per tracked object (the seed's VisNode) and scene-change detection.

For each tracking id the averager keeps, **separately for each shape kind**, the running mean of
that kind's attributes (centre, axis, radius, height, apex, point on axis, Hessian offset, a
support's extent) and how often the object was seen as that kind, each frame weighted by its fit
quality (the share of the cluster within the selection threshold of the model,
``inlier_ratio``): a frame whose flying pixels or noise spoil the fit weighs less. The object's
current primitive is its majority kind with that kind's averages, so a frame that calls a
cylinder a cone does not drag the cylinder's height or centre. Colour is averaged over every
observation.

An observation that is only a piece of an object seen whole in the same frame (``part``, from
the tracker) is left out of the averages.

Scene changes (which the seed could only handle by a manual restart): the current scene is the
set of confirmed objects. It changes when

- an object *appears*: a new id has been seen ``min_hits`` times;
- an object *vanishes*: the tracker deleted its id (after its missed-frame limit);
- an object *moves*: its cluster centroid stays more than ``move_threshold_m`` away from the
  scene's running mean for ``confirm_frames`` frames in a row (its averages then restart).

Each change emits a :class:`SceneChange`. Once the scene has gone ``stable_frames`` frames
without a change, one :class:`StableScene` is emitted with the averaged primitives; that is
what a client writes to the memory.
"""

from __future__ import annotations

import logging
from collections.abc import Iterable, Sequence
from dataclasses import dataclass, field

import numpy as np

from shapes.types import FloatArray, Primitive, ShapeKind, vec3

__all__ = ["Observation", "SceneAverager", "SceneChange", "SceneEvent", "StableScene"]

log = logging.getLogger(__name__)

_VECTORS = ("centre", "axis", "apex", "point_on_axis")
_SCALARS = ("radius", "height", "hessian_offset", "inlier_ratio")
_PAIRS = ("extent",)


@dataclass(frozen=True)
class Observation:
    """One frame's primitive for a tracked object, with its cluster's point centroid."""

    primitive: Primitive
    cluster_centroid: FloatArray
    support: bool = False
    """The primitive is a support (a table or the floor) that objects stand on."""
    part: bool = False
    """The primitive is a piece of an object whose main piece has another observation with the
    same id this frame (:attr:`shapes.track.Tracker.parts`); it is not averaged."""

    @property
    def tracking_id(self) -> int:
        """The tracker's id (the primitive must carry one)."""
        if self.primitive.tracking_id is None:
            raise ValueError("primitive.tracking_id: expected an id from the tracker, got None")
        return self.primitive.tracking_id


@dataclass(frozen=True)
class SceneChange:
    """The scene changed: its new index, and the ids that appeared, vanished or moved."""

    scene_index: int
    stamp: float | None
    appeared: tuple[int, ...]
    vanished: tuple[int, ...]
    moved: tuple[int, ...]


@dataclass(frozen=True)
class StableScene:
    """A scene's averaged primitives, by id; ``frames`` is how many frames the averages hold
    (the most any object was seen). ``partial`` marks a scene emitted at the end of a finite
    source (a file, the end of a bag) before it had held still long enough."""

    scene_index: int
    stamp: float | None
    primitives: tuple[Primitive, ...]
    votes: dict[int, dict[ShapeKind, int]]
    frames: int
    partial: bool = False
    supports: tuple[Primitive, ...] = ()
    """The Plane primitives the objects stand on (part of the scene, as in the seed's)."""


SceneEvent = SceneChange | StableScene


@dataclass
class _KindMean:
    count: int = 0
    weight: float = 0.0
    sums: dict[str, FloatArray] = field(default_factory=dict)

    def add(self, p: Primitive) -> None:
        flip = 1.0
        if p.axis is not None and "axis" in self.sums:
            flip = 1.0 if np.dot(self.sums["axis"], p.axis) >= 0 else -1.0
        for name in _VECTORS + _SCALARS + _PAIRS:
            value = getattr(p, name)
            if value is None:
                continue
            v = np.asarray(value, dtype=np.float64)
            if name == "axis" or (name == "hessian_offset" and p.kind is ShapeKind.PLANE):
                v = v * flip
            self.sums[name] = self.sums.get(name, np.zeros_like(v)) + v
        self.count += 1
        self.weight += max(p.inlier_ratio, 1e-3)

    def mean(self, kind: ShapeKind) -> dict[str, object]:
        out: dict[str, object] = {}
        for name, total in self.sums.items():
            m = total / self.count
            if name == "axis":
                m = m / max(float(np.linalg.norm(m)), 1e-12)
            if name in _PAIRS:
                out[name] = (float(m[0]), float(m[1]))
            else:
                out[name] = vec3(m) if name in _VECTORS else float(m)
        if kind is ShapeKind.PLANE and "axis" in out:
            normal = np.asarray(out["axis"], dtype=np.float64)
            out["hessian_offset"] = -float(normal @ np.asarray(out["centre"], dtype=np.float64))
        return out


@dataclass
class _Object:
    kinds: dict[ShapeKind, _KindMean] = field(default_factory=dict)
    last_seen: dict[ShapeKind, int] = field(default_factory=dict)
    colour_sum: FloatArray | None = None
    colour_n: int = 0
    ref_sum: FloatArray = field(default_factory=lambda: np.zeros(3))
    ref_n: int = 0
    hits: int = 0
    away: int = 0
    support: bool = False

    def add(self, obs: Observation, frame: int) -> None:
        p = obs.primitive
        self.support = obs.support
        self.kinds.setdefault(p.kind, _KindMean()).add(p)
        self.last_seen[p.kind] = frame
        if p.colour is not None:
            c = np.asarray(p.colour)
            self.colour_sum = c if self.colour_sum is None else self.colour_sum + c
            self.colour_n += 1
        self.ref_sum = self.ref_sum + obs.cluster_centroid
        self.ref_n += 1
        self.hits += 1

    def majority(self) -> ShapeKind:
        return max(self.kinds, key=lambda k: (self.kinds[k].weight, self.last_seen[k]))

    def primitive(self, tracking_id: int) -> Primitive:
        kind = self.majority()
        fields = self.kinds[kind].mean(kind)
        colour = None if self.colour_sum is None else vec3(self.colour_sum / self.colour_n)
        return Primitive(kind=kind, tracking_id=tracking_id, colour=colour, **fields)  # type: ignore[arg-type]


@dataclass
class SceneAverager:
    """Running averages per tracked id and a stream of scene changes and stable scenes."""

    move_threshold_m: float = 0.05
    confirm_frames: int = 3
    stable_frames: int = 5
    min_hits: int = 3
    scene_index: int = -1
    frame: int = 0
    objects: dict[int, _Object] = field(default_factory=dict)
    members: set[int] = field(default_factory=set)
    quiet_frames: int = 0
    stable_sent: bool = False

    def update(
        self,
        observations: Sequence[Observation],
        deleted: Iterable[int] = (),
        stamp: float | None = None,
    ) -> list[SceneEvent]:
        """Take one frame's observations and the ids the tracker deleted; return the events."""
        self.frame += 1
        appeared, moved = [], []
        for obs in observations:
            if obs.part:
                continue
            tid = obs.tracking_id
            obj = self.objects.setdefault(tid, _Object())
            if tid in self.members and obj.ref_n:
                ref = obj.ref_sum / obj.ref_n
                far = float(np.linalg.norm(obs.cluster_centroid - ref)) > self.move_threshold_m
                obj.away = obj.away + 1 if far else 0
                if obj.away >= self.confirm_frames:
                    moved.append(tid)
                    self.objects[tid] = obj = _Object(hits=self.min_hits)
            obj.add(obs, self.frame)
            if tid not in self.members and obj.hits >= self.min_hits:
                appeared.append(tid)
        vanished = []
        for tid in deleted:
            if tid in self.members:
                vanished.append(tid)
                self.members.discard(tid)
            self.objects.pop(tid, None)
        self.members.update(appeared)
        events: list[SceneEvent] = []
        if appeared or vanished or moved:
            self.scene_index += 1
            self.quiet_frames, self.stable_sent = 0, False
            change = SceneChange(
                self.scene_index, stamp, tuple(appeared), tuple(sorted(vanished)), tuple(moved)
            )
            log.info(
                "scene %d: appeared %s, vanished %s, moved %s",
                change.scene_index,
                change.appeared,
                change.vanished,
                change.moved,
            )
            events.append(change)
        elif self.scene_index >= 0:
            self.quiet_frames += 1
            if self.quiet_frames >= self.stable_frames and not self.stable_sent:
                self.stable_sent = True
                events.append(self.stable_scene(stamp))
        return events

    def stable_scene(self, stamp: float | None = None) -> StableScene:
        """The current averaged scene (what :meth:`update` emits once it holds still)."""
        return self._scene(sorted(self.members), stamp, partial=False)

    def _scene(self, ids: list[int], stamp: float | None, *, partial: bool) -> StableScene:
        objects = [i for i in ids if not self.objects[i].support]
        return StableScene(
            max(self.scene_index, 0),
            stamp,
            tuple(self.objects[i].primitive(i) for i in objects),
            {i: {k: m.count for k, m in self.objects[i].kinds.items()} for i in ids},
            max((self.objects[i].hits for i in objects), default=0),
            partial,
            tuple(self.objects[i].primitive(i) for i in ids if self.objects[i].support),
        )

    def flush(self, stamp: float | None = None) -> StableScene | None:
        """At the end of a finite source: the scene it has, if none was emitted for it yet.

        Every confirmed object counts, and every object seen in at least
        ``min(min_hits, frames seen)`` frames, so one scan gives the scene of that scan.
        Returns None when there is no such object or the scene was already emitted.
        """
        if self.stable_sent:
            return None
        need = min(self.min_hits, max(self.frame, 1))
        ids = sorted(i for i, o in self.objects.items() if i in self.members or o.hits >= need)
        if all(self.objects[i].support for i in ids):
            return None
        self.stable_sent = True
        return self._scene(ids, stamp, partial=True)
