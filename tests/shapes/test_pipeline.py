"""The whole chain on synthetic tabletop frames: segmentation, shapes, ids, averages, scenes."""

import math
from dataclasses import dataclass, replace

import numpy as np
import pytest

from shapes import (
    Frame,
    FrameResult,
    Perception,
    SceneChange,
    ShapeKind,
    StableScene,
    colour_name,
    pipeline,
)
from shapes.fit import fit_cluster
from shapes.segment import segment
from shapes.synthetic import PALETTE, TabletopScene, TruthObject

SCENE = TabletopScene(
    (
        TruthObject("Sphere", (-0.25, 0.0, 0.0), radius=0.05, height=0.10, colour=PALETTE["red"]),
        TruthObject(
            "Cylinder", (-0.05, 0.12, 0.0), radius=0.035, height=0.14, colour=PALETTE["green"]
        ),
        TruthObject("Cone", (0.15, 0.0, 0.0), radius=0.05, height=0.12, colour=PALETTE["blue"]),
        TruthObject(
            "Box", (0.30, 0.15, 0.0), size=(0.08, 0.06, 0.10), yaw=0.5, colour=PALETTE["yellow"]
        ),
    )
)
FRAMES = 30


def nearest_object(scene, centre):
    """Index of the truth object whose footprint centre is nearest (in xy) to ``centre``."""
    return min(
        range(len(scene.objects)),
        key=lambda k: math.dist(scene.objects[k].position[:2], centre[:2]),
    )


@dataclass
class Run:
    """One stream through one Perception: 30 still frames, 10 with the sphere moved 10 cm,
    then 9 with the cone taken away (the chain's state carries over, as on a robot)."""

    perception: Perception
    still: list[FrameResult]
    averaged: StableScene
    moved: list[FrameResult]
    removed: list[FrameResult]


@pytest.fixture(scope="module")
def run() -> Run:
    rng = np.random.default_rng(11)
    perception = Perception(seed=5)
    still = [perception.process(SCENE.render(rng, stamp=float(i)).frame) for i in range(FRAMES)]
    averaged = perception.averager.stable_scene()
    moved_scene = SCENE.moved(0, 0.0, -0.10)
    moved = [perception.process(moved_scene.render(rng).frame) for _ in range(10)]
    gone = moved_scene.without(2)
    removed = [perception.process(gone.render(rng).frame) for _ in range(9)]
    return Run(perception, still, averaged, moved, removed)


def test_every_object_is_found_with_the_right_shape():
    rng = np.random.default_rng(2)
    shot = SCENE.render(rng)
    seg = segment(shot.frame)
    assert seg.support is not None
    np.testing.assert_allclose(seg.support.normal, (0, 0, 1), atol=0.01)
    assert len(seg.clusters) == len(SCENE.objects)
    found = {}
    for cluster in seg.clusters:
        fit = fit_cluster(cluster.points, support=seg.support, rng=np.random.default_rng(0))
        found[nearest_object(SCENE, cluster.centroid)] = fit.primitive.kind
    assert found == {k: o.expected_kind for k, o in enumerate(SCENE.objects)}


def test_ids_stay_the_same_over_30_noisy_frames(run):
    results = run.still
    ids_per_object: dict[int, set[int]] = {}
    for result in results:
        assert len(result.primitives) == len(SCENE.objects)
        for p in result.primitives:
            ids_per_object.setdefault(nearest_object(SCENE, p.centre), set()).add(p.tracking_id)
    assert all(len(ids) == 1 for ids in ids_per_object.values()), ids_per_object
    assert len({next(iter(ids)) for ids in ids_per_object.values()}) == len(SCENE.objects)
    # No id was made twice: every id the tracker handed out belongs to one of the objects.
    assert {r.primitives[0].tracking_id for r in results} <= set(range(len(SCENE.objects)))
    assert max(p.tracking_id for r in results for p in r.primitives) == len(SCENE.objects) - 1


def test_shapes_are_right_in_every_frame(run):
    for result in run.still:
        for p in result.primitives:
            assert p.kind is SCENE.objects[nearest_object(SCENE, p.centre)].expected_kind


def test_averaged_attributes_converge_toward_the_truth(run):
    results, scene = run.still, run.averaged
    assert len(scene.primitives) == len(SCENE.objects)
    for avg in scene.primitives:
        truth = SCENE.objects[nearest_object(SCENE, avg.centre)]
        assert avg.kind is truth.expected_kind
        if truth.kind == "Box":
            continue
        frames = [p for r in results for p in r.primitives if p.tracking_id == avg.tracking_id]
        radius_errors = [abs(p.radius - truth.radius) for p in frames]
        centre_errors = [math.dist(p.centre, truth.centre) for p in frames]
        np.testing.assert_allclose(avg.radius, truth.radius, atol=0.0015)
        np.testing.assert_allclose(avg.centre, truth.centre, atol=0.003)
        # The average is at least as close as a typical single frame.
        assert abs(avg.radius - truth.radius) <= np.median(radius_errors) + 2e-4
        assert math.dist(avg.centre, truth.centre) <= np.median(centre_errors) + 2e-4
        if truth.kind in ("Cylinder", "Cone"):
            np.testing.assert_allclose(avg.height, truth.height, atol=0.004)
            np.testing.assert_allclose(abs(avg.axis[2]), 1.0, atol=0.002)


def test_each_object_gets_its_colour(run):
    for p in run.still[-1].primitives:
        truth = SCENE.objects[nearest_object(SCENE, p.centre)]
        np.testing.assert_allclose(p.colour, truth.colour, atol=0.02)
        expected = next(name for name, rgb in PALETTE.items() if rgb == truth.colour)
        assert colour_name(np.array([p.colour])) == expected


def test_the_scene_stream_has_one_change_then_one_stable_scene(run):
    events = [e for r in run.still for e in r.events]
    assert [type(e) for e in events] == [SceneChange, StableScene]
    change, stable = events
    assert change.scene_index == stable.scene_index == 0
    assert sorted(change.appeared) == [p.tracking_id for p in stable.primitives + stable.supports]
    assert {p.kind for p in stable.primitives} == {o.expected_kind for o in SCENE.objects}
    assert [p.kind for p in stable.supports] == [ShapeKind.PLANE]


def test_a_moved_object_starts_a_new_scene(run):
    sphere_id = next(p.tracking_id for p in run.averaged.primitives if p.kind is ShapeKind.SPHERE)
    events = [e for r in run.moved for e in r.events]
    changes = [e for e in events if isinstance(e, SceneChange)]
    stables = [e for e in events if isinstance(e, StableScene)]
    assert [(c.moved, c.appeared, c.vanished) for c in changes] == [((sphere_id,), (), ())]
    assert len(stables) == 1 and stables[0].scene_index == changes[0].scene_index == 1
    sphere = next(p for p in stables[0].primitives if p.tracking_id == sphere_id)
    np.testing.assert_allclose(
        sphere.centre, SCENE.moved(0, 0.0, -0.10).objects[0].centre, atol=0.003
    )


def test_a_removed_object_vanishes_from_the_next_scene(run):
    cone_id = next(p.tracking_id for p in run.averaged.primitives if p.kind is ShapeKind.CONE)
    events = [e for r in run.removed for e in r.events]
    changes = [e for e in events if isinstance(e, SceneChange)]
    assert [(c.scene_index, c.vanished, c.appeared, c.moved) for c in changes] == [
        (2, (cone_id,), (), ())
    ]
    stable = next(e for e in events if isinstance(e, StableScene))
    assert stable.scene_index == 2
    assert {p.tracking_id for p in stable.primitives} == {
        p.tracking_id for p in run.averaged.primitives
    } - {cone_id}


def test_a_frame_without_a_table_gives_no_object_and_ages_the_tracks():
    rng = np.random.default_rng(3)
    perception = Perception(seed=0)
    first = perception.process(SCENE.render(rng).frame)
    assert len(first.primitives) == 4
    # A bare wall: no horizontal plane to stand on.
    wall = np.column_stack((rng.uniform(-0.5, 0.5, 3000), np.ones(3000), rng.uniform(0, 1, 3000)))
    for _ in range(3):
        result = perception.process(Frame(wall))  # no colours either
        assert result.support is None and result.primitives == ()
    assert perception.tracker.tracks == {}  # every track missed three frames and was deleted


def test_the_chain_is_deterministic_under_a_seed():
    rng = np.random.default_rng(9)
    frames = [SCENE.render(rng).frame for _ in range(2)]
    first = [r.primitives for r in Perception(seed=3).run(frames)]
    second = [r.primitives for r in Perception(seed=3).run(frames)]
    assert first == second


def test_a_cluster_fits_the_same_whatever_the_other_clusters(monkeypatch):
    frame = SCENE.render(np.random.default_rng(4)).frame
    whole = Perception(seed=2).process(frame)
    assert len(whole.primitives) == 4
    real_segment = pipeline.segment

    def without_the_first_cluster(*args, **kwargs):
        found = real_segment(*args, **kwargs)
        return replace(found, clusters=found.clusters[1:])

    monkeypatch.setattr(pipeline, "segment", without_the_first_cluster)
    fewer = Perception(seed=2).process(frame)
    # Everything but the tracking ids (given in order) is the same, to the last bit.
    assert [replace(p, tracking_id=None) for p in fewer.primitives] == [
        replace(p, tracking_id=None) for p in whole.primitives[1:]
    ]
