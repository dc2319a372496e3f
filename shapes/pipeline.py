"""The whole perception chain for a stream of frames: segment, fit, track, colour, average.

>>> from shapes.synthetic import random_scene
>>> rng = np.random.default_rng(7)
>>> scene = random_scene(rng, n_objects=2, kinds=("Sphere",))
>>> perception = Perception(seed=0)
>>> results = [perception.process(scene.render(rng).frame) for _ in range(8)]
>>> [p.kind.value for p in results[-1].primitives]
['Sphere', 'Sphere']
>>> [type(e).__name__ for r in results for e in r.events]
['SceneChange', 'StableScene']
"""

from __future__ import annotations

import logging
from collections.abc import Iterable, Iterator
from dataclasses import dataclass, field, replace

import numpy as np

from shapes.average import Observation, SceneAverager, SceneEvent, StableScene
from shapes.colour import mean_colour
from shapes.fit import FitParams, fit_cluster
from shapes.frame import Frame
from shapes.gravity import gravity_from_survey
from shapes.segment import Cluster, Segmentation, SegmentationParams, segment, survey
from shapes.track import Tracker, box_of
from shapes.types import FloatArray, Primitive, ShapeKind, SupportPlane

__all__ = ["FrameResult", "Perception", "PerceptionParams"]

log = logging.getLogger(__name__)


@dataclass(frozen=True)
class PerceptionParams:
    """Every knob of the chain; the defaults are PITT's where PITT had one (see each stage)."""

    segmentation: SegmentationParams = field(default_factory=SegmentationParams)
    fit: FitParams = field(default_factory=FitParams)
    gate_m: float = 0.20
    forget_after: int = 3
    weight_old: float = 0.6
    weight_new: float = 0.4
    move_threshold_m: float = 0.05
    confirm_frames: int = 3
    stable_frames: int = 5
    min_hits: int = 3
    gravity_from_scene: bool = False
    """Ignore the frames' poses and take up from each frame's dominant support
    (:mod:`shapes.gravity`): for a sensor whose pose is not known."""


@dataclass(frozen=True, eq=False)
class FrameResult:
    """One frame's output: the support, this frame's primitives (with ids), and scene events."""

    index: int
    stamp: float | None
    support: SupportPlane | None
    primitives: tuple[Primitive, ...]
    events: tuple[SceneEvent, ...]
    centroids: tuple[FloatArray, ...] = ()
    reason: str | None = None
    """Why this frame gave no primitive (one line), None when it gave some."""
    gravity: str = "pose"
    """Where up came from: "pose" (the frame's world_from_sensor) or a line from
    :meth:`shapes.gravity.Gravity.describe`."""
    supports: tuple[Primitive, ...] = ()
    """The supports under this frame's primitives, as Plane primitives (with ids)."""
    world_from_sensor: FloatArray = field(default_factory=lambda: np.eye(4))
    """The pose the frame was processed with (the frame's own, or gravity's)."""


def _signature(primitive: Primitive) -> tuple[str, float]:
    """Shape kind and size (radius, or 0 for a plane) by which a moved object is known again."""
    return primitive.kind.value, primitive.radius or 0.0


def _supports_under(
    fitted: list[tuple[Cluster, Primitive]], seg: Segmentation
) -> list[tuple[Cluster, Primitive]]:
    """The supports the fitted objects stand on, each as a Plane primitive of the scene: the
    plane measured again over the support's main piece (:meth:`Segmentation.reported`).

    The plane's ``centre`` is the mean of the support's own points (on the plane): an object
    added to the scene or taken away leaves the relations of the others to the support as
    they were, so a scene with one more object is a specialisation of the scene without it.
    """
    out: list[tuple[Cluster, Primitive]] = []
    found = dict.fromkeys(c.support for c, _ in fitted if c.support is not None)
    for support in (seg.reported(plane) for plane in found):
        if support.centre is None:
            continue
        centre = np.asarray(support.centre)
        primitive = Primitive(
            ShapeKind.PLANE,
            support.centre,
            axis=support.normal,
            hessian_offset=-float(np.asarray(support.normal) @ centre),
            extent=support.extent,
        )
        out.append((Cluster(centre[None, :], None, centre[None, :], support), primitive))
    return out


class Perception:
    """Stateful chain: call :meth:`process` once per frame, in order.

    Deterministic for a given ``seed``. In frame k, each cluster's fit draws from a fresh
    generator seeded with ``(seed, k)``, so one cluster's fit does not depend on the other
    clusters of the frame (how many there are, their order, their sizes).
    """

    def __init__(self, params: PerceptionParams | None = None, *, seed: int = 0) -> None:
        self.params = params or PerceptionParams()
        p = self.params
        self.seed = seed
        self.frames = 0
        self.tracker = Tracker(p.gate_m, p.forget_after, p.weight_old, p.weight_new)
        self.averager = SceneAverager(
            p.move_threshold_m, p.confirm_frames, p.stable_frames, p.min_hits
        )
        self.reasons: dict[str, str] = {}
        self.last_stamp: float | None = None
        self.gravity = "pose"
        """Where up came from in the last frame (:attr:`FrameResult.gravity`)."""

    def process(self, frame: Frame) -> FrameResult:
        """Run one frame through the chain."""
        index = self.frames
        self.frames += 1
        gravity = "pose"
        surveyed = survey(frame, self.params.segmentation, self.seed + index)
        if self.params.gravity_from_scene:
            found = gravity_from_survey(frame, surveyed, self.params.segmentation)
            if found is None:
                gravity = "gravity from the scene: no plane found, the sensor's z axis is up"
                frame = frame.with_pose(np.eye(4))
            else:
                gravity = found.describe()
                frame = frame.with_pose(found.world_from_sensor)
        self.gravity = gravity
        seg = segment(frame, self.params.segmentation, self.seed + index, surveyed=surveyed)
        # The sensor's centre in the world frame: fit_cluster scores the sphere along its rays.
        viewpoint = frame.world_from_sensor[:3, 3] if surveyed.in_camera_frame else None
        fitted = []
        for cluster in seg.clusters:
            # A fresh generator per cluster: no fit depends on the frame's other clusters.
            rng = np.random.default_rng([self.seed, index])
            fit = fit_cluster(
                cluster.points,
                support=cluster.support or seg.support,
                params=self.params.fit.for_noise(cluster.noise_m),
                rng=rng,
                viewpoint=viewpoint,
            )
            if fit is not None:
                fitted.append((cluster, fit.primitive))
        supports = _supports_under(fitted, seg)
        reason = seg.reason
        if seg.clusters and not fitted:
            reason = f"clusters rejected: no model fits any of the {len(seg.clusters)} cluster(s)"
        if reason is not None:
            self.reasons[reason.split(":")[0]] = reason
        self.last_stamp = frame.stamp
        tracked = fitted + supports
        ids = self.tracker.update(
            [c.centroid for c, _ in tracked],
            [_signature(p) for _, p in tracked],
            [box_of(c.points) for c, _ in tracked],
        )
        primitives: list[Primitive] = []
        planes: list[Primitive] = []
        observations: list[Observation] = []
        for k, ((cluster, prim), tid) in enumerate(zip(tracked, ids, strict=True)):
            colour = None if cluster.colours is None else mean_colour(cluster.colours)
            prim = replace(prim, tracking_id=tid, colour=colour, stamp=frame.stamp)
            (primitives if k < len(fitted) else planes).append(prim)
            observations.append(
                Observation(
                    prim, cluster.centroid, support=k >= len(fitted), part=self.tracker.parts[k]
                )
            )
        events = self.averager.update(observations, self.tracker.deleted, frame.stamp)
        log.debug("frame %d: %d primitives, %d events", index, len(primitives), len(events))
        return FrameResult(
            index,
            frame.stamp,
            seg.support,
            tuple(primitives),
            tuple(events),
            tuple(o.cluster_centroid for o in observations[: len(primitives)]),
            reason,
            gravity,
            tuple(planes),
            frame.world_from_sensor,
        )

    def finish(self) -> StableScene | None:
        """The end of a finite source: the scene it has, averaged over the frames seen, if no
        stable scene was emitted for it (:meth:`SceneAverager.flush`)."""
        return self.averager.flush(self.last_stamp)

    def why_no_scene(self) -> list[str]:
        """One line per reason the frames so far gave no scene (the last frame's wording for
        each cause), and "not stable yet" when objects were seen but no scene held still."""
        lines = list(self.reasons.values())
        if self.averager.objects and not self.averager.stable_sent:
            p = self.params
            lines.append(
                f"not stable yet: {self.frames} frame(s) seen, a scene needs its objects seen "
                f"{p.min_hits} times and then {p.stable_frames} frames without a change"
            )
        return lines

    def run(self, frames: Iterable[Frame]) -> Iterator[FrameResult]:
        """Process frames lazily, one result per frame."""
        for frame in frames:
            yield self.process(frame)

    def stable_scenes(
        self, frames: Iterable[Frame], *, finish: bool = False
    ) -> Iterator[StableScene]:
        """Only the stable scenes of a stream: what a memory client consumes.

        ``finish``: the stream is finite (a file, a bag); at its end, emit the scene it has if
        it did not hold still long enough (:meth:`finish`).
        """
        for result in self.run(frames):
            for event in result.events:
                if isinstance(event, StableScene):
                    yield event
        if finish:
            last = self.finish()
            if last is not None:
                yield last
