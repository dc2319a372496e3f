"""Tracker, averaging and scene changes on hand-made inputs."""

import numpy as np
import pytest

from shapes import (
    Observation,
    Primitive,
    SceneAverager,
    SceneChange,
    ShapeKind,
    StableScene,
    Tracker,
)


def c(*xyz):
    return np.array(xyz, dtype=float)


def test_ids_follow_the_nearest_centroid_within_the_gate():
    t = Tracker()
    assert t.update([c(0, 0, 0), c(0.5, 0, 0)]) == [0, 1]
    assert t.update([c(0.52, 0, 0), c(0.03, 0, 0)]) == [1, 0]
    assert t.update([c(0.9, 0, 0)]) == [2]  # 0.38 m from the nearest track: a new object


def test_the_centroid_is_smoothed_with_pitt_weights():
    t = Tracker()
    t.update([c(0, 0, 0)])
    t.update([c(0.1, 0, 0)])
    np.testing.assert_allclose(t.tracks[0].centroid, [0.04, 0, 0])  # 0.6 * 0 + 0.4 * 0.1


def test_a_track_is_deleted_after_three_missed_frames_and_its_id_never_returns():
    t = Tracker()
    t.update([c(0, 0, 0)])
    t.update([])
    t.update([])
    assert 0 in t.tracks and t.deleted == []
    t.update([])  # empty frames age tracks too
    assert 0 not in t.tracks and t.deleted == [0]
    assert t.update([c(0, 0, 0)]) == [1]


def test_two_detections_near_one_track_do_not_drop_either():
    """PITT dropped the second detection whose nearest track was taken; here it starts a track."""
    t = Tracker()
    t.update([c(0, 0, 0)])
    assert t.update([c(0.05, 0, 0), c(0.02, 0, 0)]) == [1, 0]


@pytest.mark.parametrize(
    "kwargs", [{"gate_m": 0.0}, {"forget_after": 0}, {"weight_new": 0.0}, {"weight_old": -1.0}]
)
def test_tracker_parameters_are_checked(kwargs):
    with pytest.raises(ValueError, match="Tracker: expected gate_m > 0"):
        Tracker(**kwargs)


def obs(tid, kind, centre, **fields):
    return Observation(Primitive(kind, centre=centre, tracking_id=tid, **fields), c(*centre))


def test_averages_are_kept_per_shape_and_the_majority_wins():
    avg = SceneAverager(min_hits=1)
    cyl = {"axis": (0, 0, 1), "radius": 0.03, "height": 0.10}
    avg.update([obs(7, ShapeKind.CYLINDER, (0, 0, 0.05), **cyl)])
    avg.update(
        [obs(7, ShapeKind.CYLINDER, (0, 0, 0.07), **{**cyl, "axis": (0, 0, -1), "radius": 0.05})]
    )
    avg.update(
        [
            obs(
                7,
                ShapeKind.CONE,
                (0, 0, 0.025),
                axis=(0, 0, -1),
                radius=0.03,
                height=0.1,
                apex=(0, 0, 0.1),
            )
        ]
    )
    (p,) = avg.stable_scene().primitives
    assert p.kind is ShapeKind.CYLINDER and p.tracking_id == 7
    np.testing.assert_allclose(p.centre, (0, 0, 0.06))  # the cone's centre is kept apart
    np.testing.assert_allclose(p.radius, 0.04)
    np.testing.assert_allclose(p.axis, (0, 0, 1))  # opposite signs of one axis agree
    assert avg.stable_scene().votes == {7: {ShapeKind.CYLINDER: 2, ShapeKind.CONE: 1}}


def test_plane_offsets_follow_the_averaged_normal():
    avg = SceneAverager(min_hits=1)
    avg.update([obs(1, ShapeKind.PLANE, (0, 0, 0.1), axis=(0, 0, 1), hessian_offset=-0.1)])
    avg.update([obs(1, ShapeKind.PLANE, (0, 0, 0.1), axis=(0, 0, -1), hessian_offset=0.1)])
    (p,) = avg.stable_scene().primitives
    np.testing.assert_allclose(p.axis, (0, 0, 1))
    np.testing.assert_allclose(p.hessian_offset, -0.1)


def test_scene_events_appear_move_vanish_and_settle():
    avg = SceneAverager(move_threshold_m=0.05, confirm_frames=2, stable_frames=2, min_hits=2)
    s = {"radius": 0.05}
    kinds = ShapeKind.SPHERE
    log = []
    for _ in range(4):
        log += avg.update([obs(0, kinds, (0, 0, 0.05), **s)])
    for _ in range(4):  # moved by 10 cm
        log += avg.update([obs(0, kinds, (0.1, 0, 0.05), **s)])
    log += avg.update([], deleted=[0])
    log += avg.update([])
    log += avg.update([])
    assert [type(e).__name__ for e in log] == [
        "SceneChange",
        "StableScene",
        "SceneChange",
        "StableScene",
        "SceneChange",
        "StableScene",
    ]
    changes = [e for e in log if isinstance(e, SceneChange)]
    assert [(e.appeared, e.moved, e.vanished) for e in changes] == [
        ((0,), (), ()),
        ((), (0,), ()),
        ((), (), (0,)),
    ]
    stables = [e for e in log if isinstance(e, StableScene)]
    np.testing.assert_allclose(stables[1].primitives[0].centre, (0.1, 0, 0.05))
    assert stables[2].primitives == ()


def test_an_observation_needs_a_tracking_id():
    with pytest.raises(ValueError, match="tracking_id"):
        _ = Observation(Primitive(ShapeKind.SPHERE, centre=(0, 0, 0)), c(0, 0, 0)).tracking_id


def test_an_object_moved_beyond_the_gate_keeps_its_id_by_its_shape_and_size():
    t = Tracker(gate_m=0.2)
    can, ball = ("Cylinder", 0.04), ("Sphere", 0.05)
    first = t.update([np.array([0.0, 0.0, 0.1]), np.array([0.3, 0.0, 0.1])], [can, ball])
    moved = t.update([np.array([0.0, 0.5, 0.1]), np.array([0.3, 0.0, 0.1])], [can, ball])
    assert moved == first
    # A different shape that far away is a new object.
    other = t.update([np.array([0.6, 0.5, 0.1]), np.array([0.3, 0.0, 0.1])], [ball, ball])
    assert other[0] not in first and other[1] == first[1]


def test_the_majority_shape_weighs_each_frame_by_its_fit_quality():
    avg = SceneAverager(min_hits=1)
    good = Primitive(ShapeKind.CONE, centre=(0, 0, 0.03), radius=0.04, height=0.1, tracking_id=0)
    for ratio, kind in ((0.95, ShapeKind.CONE), (0.3, ShapeKind.PLANE), (0.3, ShapeKind.PLANE)):
        prim = Primitive(kind, centre=good.centre, tracking_id=0, inlier_ratio=ratio)
        if kind is ShapeKind.CONE:
            prim = good
        avg.update([Observation(prim, np.zeros(3))])
    assert avg.stable_scene().primitives[0].kind is ShapeKind.CONE
