"""Primitive fitting on clouds that can be checked by hand, and the shape-choice rule."""

import numpy as np
import pytest

from shapes.fit import fit_cluster, pitt_choice
from shapes.fit._ransac import ransac
from shapes.fit.models import ConeModel, CylinderModel, SphereModel
from shapes.types import ShapeKind, SupportPlane

TABLE = SupportPlane((0.0, 0.0, 1.0), 0.0)


def front_sphere(rng: np.random.Generator, centre, radius, n=1500):
    """Points on the half of a sphere that faces a camera looking along +y."""
    u = rng.normal(size=(2 * n, 3))
    u /= np.linalg.norm(u, axis=1)[:, None]
    return np.asarray(centre) + radius * u[u[:, 1] < 0][:n]


def cylinder_side(rng, base, axis, radius, height, n=1500, arc=np.pi):
    a = np.asarray(axis, dtype=float) / np.linalg.norm(axis)
    e1 = np.cross(a, [1.0, 0.0, 0.0])
    e1 /= np.linalg.norm(e1)
    e2 = np.cross(a, e1)
    theta = rng.uniform(0, arc, n)
    t = rng.uniform(0, height, n)
    ring = np.outer(np.cos(theta), e1) + np.outer(np.sin(theta), e2)
    return np.asarray(base) + np.outer(t, a) + radius * ring


def upright_cone(rng, apex, radius, height, n=1500, arc=2 * np.pi):
    """Lateral surface of a cone standing on its base, apex up."""
    z = height * np.sqrt(rng.uniform(0, 1, n))  # area-uniform
    phi = rng.uniform(0, arc, n)
    r = radius * z / height
    return np.column_stack((apex[0] + r * np.cos(phi), apex[1] + r * np.sin(phi), apex[2] - z))


def test_perfect_sphere_gives_its_centre_and_radius():
    rng = np.random.default_rng(0)
    points = front_sphere(rng, (0.1, 0.2, 0.05), 0.04)
    fit = fit_cluster(points, rng=np.random.default_rng(1))
    assert fit is not None
    p = fit.primitive
    assert p.kind is ShapeKind.SPHERE
    np.testing.assert_allclose(p.centre, (0.1, 0.2, 0.05), atol=1e-6)
    np.testing.assert_allclose(p.radius, 0.04, atol=1e-6)
    assert p.inlier_ratio == 1.0


def test_cylinder_with_a_known_tilted_axis():
    rng = np.random.default_rng(0)
    axis = np.array([1.0, 0.5, 2.0]) / np.linalg.norm([1.0, 0.5, 2.0])
    base = np.array([0.0, 0.1, 0.02])
    points = cylinder_side(rng, base, axis, 0.03, 0.12)
    p = fit_cluster(points, rng=np.random.default_rng(1)).primitive
    assert p.kind is ShapeKind.CYLINDER
    np.testing.assert_allclose(np.abs(np.dot(p.axis, axis)), 1.0, atol=1e-9)
    np.testing.assert_allclose(p.radius, 0.03, atol=1e-6)
    np.testing.assert_allclose(p.height, 0.12, atol=0.002)
    np.testing.assert_allclose(p.centre, base + 0.06 * axis, atol=0.001)
    # The point on the axis lies on the true axis line.
    off = np.asarray(p.point_on_axis) - base
    np.testing.assert_allclose(np.linalg.norm(off - (off @ axis) * axis), 0.0, atol=1e-6)


def test_cone_with_a_known_apex():
    rng = np.random.default_rng(0)
    apex = np.array([0.2, 0.0, 0.15])
    points = upright_cone(rng, apex, 0.05, 0.10)
    support = SupportPlane((0.0, 0.0, 1.0), -0.05)  # the base sits on z = 0.05
    p = fit_cluster(points, support=support, rng=np.random.default_rng(1)).primitive
    assert p.kind is ShapeKind.CONE
    np.testing.assert_allclose(p.apex, apex, atol=1e-6)
    np.testing.assert_allclose(p.axis, (0.0, 0.0, -1.0), atol=1e-6)  # apex to base
    np.testing.assert_allclose(p.height, 0.10, atol=1e-6)
    np.testing.assert_allclose(p.radius, 0.05, atol=1e-6)
    np.testing.assert_allclose(p.half_angle, np.arctan(0.5), atol=1e-6)
    np.testing.assert_allclose(p.centre, (0.2, 0.0, 0.075), atol=1e-6)  # solid centroid


def test_sphere_model_passes_through_four_points():
    pts = np.array([[1.0, 0, 0], [-1.0, 0, 0], [0, 1.0, 0], [0, 0, 1.0]]) * 0.1 + 0.5
    params, ok = SphereModel().hypotheses(pts, np.zeros_like(pts), np.array([[0, 1, 2, 3]]))
    assert ok[0]
    np.testing.assert_allclose(params[0], [0.5, 0.5, 0.5, 0.1], atol=1e-12)


def test_cylinder_model_from_two_points_with_normals():
    pts = np.array([[0.05, 0.0, 0.0], [0.0, 0.05, 0.3]])
    normals = np.array([[1.0, 0.0, 0.0], [0.0, 1.0, 0.0]])
    params, ok = CylinderModel().hypotheses(pts, normals, np.array([[0, 1]]))
    assert ok[0]
    np.testing.assert_allclose(np.abs(params[0, 3:6]), [0, 0, 1], atol=1e-12)
    np.testing.assert_allclose(params[0, 6], 0.05, atol=1e-12)
    np.testing.assert_allclose(params[0, :2], [0, 0], atol=1e-12)


def test_cone_model_from_three_points_with_normals():
    theta = np.radians(30)
    pts, normals = [], []
    for phi in (0.0, 2.0, 4.0):
        radial = np.array([np.cos(phi), np.sin(phi), 0.0])
        k = 0.1 * (1 + phi / 10)
        pts.append(
            np.array([0, 0, 1.0])
            - k * np.cos(theta) * np.array([0, 0, 1.0])
            + k * np.sin(theta) * radial
        )
        normals.append(np.cos(theta) * radial + np.sin(theta) * np.array([0, 0, 1.0]))
    params, ok = ConeModel().hypotheses(np.array(pts), np.array(normals), np.array([[0, 1, 2]]))
    assert ok[0]
    np.testing.assert_allclose(params[0, :3], [0, 0, 1.0], atol=1e-9)
    np.testing.assert_allclose(params[0, 3:6], [0, 0, -1.0], atol=1e-9)
    np.testing.assert_allclose(params[0, 6], theta, atol=1e-9)


def test_fitting_is_deterministic_under_a_seed():
    rng = np.random.default_rng(3)
    points = front_sphere(rng, (0, 0, 0.05), 0.05) + rng.normal(0, 0.002, (1500, 3))
    a = fit_cluster(points, rng=np.random.default_rng(9))
    b = fit_cluster(points, rng=np.random.default_rng(9))
    assert a.primitive == b.primitive and a.costs == b.costs


def test_a_cylinder_whose_flat_top_dominates_stays_a_cylinder():
    """A wide, short can seen from above: the top disc holds most points. PITT's raw inlier
    count does not call it a cylinder; the surface-cost rule counts the disc as part of it."""
    rng = np.random.default_rng(5)
    side = cylinder_side(rng, (0, 0, 0), (0, 0, 1), 0.06, 0.06, n=800)
    r = 0.06 * np.sqrt(rng.uniform(0, 1, 1200))
    phi = rng.uniform(0, 2 * np.pi, 1200)
    top = np.column_stack((r * np.cos(phi), r * np.sin(phi), np.full(1200, 0.06)))
    points = np.vstack((side, top)) + rng.normal(0, 0.0015, (2000, 3))
    fit = fit_cluster(points, support=TABLE, rng=np.random.default_rng(1))
    assert pitt_choice(fit.pitt_counts) is not ShapeKind.CYLINDER
    p = fit.primitive
    assert p.kind is ShapeKind.CYLINDER
    np.testing.assert_allclose(p.radius, 0.06, atol=0.002)
    np.testing.assert_allclose(p.height, 0.06, atol=0.002)


def test_height_reaches_the_support_although_the_bottom_was_cut_away():
    """Segmentation drops the lowest centimetre with the table; the fit snaps the base back."""
    rng = np.random.default_rng(2)
    points = cylinder_side(rng, (0.1, 0.1, 0.0), (0, 0, 1), 0.03, 0.15, n=2000)
    points = points[points[:, 2] > 0.012]  # what is left above the support margin
    p = fit_cluster(points, support=TABLE, rng=np.random.default_rng(1)).primitive
    assert p.kind is ShapeKind.CYLINDER
    np.testing.assert_allclose(p.height, 0.15, atol=0.002)
    np.testing.assert_allclose(p.point_on_axis, (0.1, 0.1, 0.0), atol=1e-3)
    np.testing.assert_allclose(p.centre, (0.1, 0.1, 0.075), atol=0.002)


def test_box_faces_are_reported_as_a_plane_with_an_outward_normal():
    rng = np.random.default_rng(4)
    top = np.column_stack(
        (rng.uniform(-0.04, 0.04, 800), rng.uniform(-0.03, 0.03, 800), np.full(800, 0.1))
    )
    front = np.column_stack(
        (rng.uniform(-0.04, 0.04, 600), np.full(600, -0.03), rng.uniform(0.0, 0.1, 600))
    )
    points = np.vstack((top, front)) + rng.normal(0, 0.001, (1400, 3))
    p = fit_cluster(points, support=TABLE, rng=np.random.default_rng(1)).primitive
    assert p.kind is ShapeKind.PLANE
    np.testing.assert_allclose(p.axis, (0, 0, 1), atol=0.01)  # the largest face, pointing out
    np.testing.assert_allclose(p.hessian_offset, -0.1, atol=0.001)
    np.testing.assert_allclose(np.dot(p.axis, p.centre) + p.hessian_offset, 0.0, atol=1e-9)


@pytest.mark.parametrize(
    ("counts", "expected"),
    [
        ({ShapeKind.SPHERE: 0, ShapeKind.CYLINDER: 0, ShapeKind.CONE: 0, ShapeKind.PLANE: 0}, None),
        (
            {ShapeKind.SPHERE: 5, ShapeKind.CYLINDER: 100, ShapeKind.CONE: 90, ShapeKind.PLANE: 10},
            ShapeKind.CONE,
        ),
        (
            {ShapeKind.SPHERE: 5, ShapeKind.CYLINDER: 100, ShapeKind.CONE: 89, ShapeKind.PLANE: 10},
            ShapeKind.CYLINDER,
        ),
        (
            {ShapeKind.SPHERE: 50, ShapeKind.CYLINDER: 10, ShapeKind.CONE: 10, ShapeKind.PLANE: 60},
            ShapeKind.PLANE,
        ),
        (
            {ShapeKind.SPHERE: 70, ShapeKind.CYLINDER: 10, ShapeKind.CONE: 10, ShapeKind.PLANE: 60},
            ShapeKind.SPHERE,
        ),
    ],
)
def test_pitt_choice_reproduces_the_original_rule(counts, expected):
    assert pitt_choice(counts) is expected


def test_too_few_points_give_no_fit():
    assert fit_cluster(np.zeros((5, 3)), rng=np.random.default_rng(0)) is None


def test_a_cone_is_found_from_its_base_disc_and_a_strip_of_its_side():
    # A cone lying with its base toward the camera: a full disc of 6 cm and a narrow strip of
    # the lateral surface, the apex 10 cm behind the base centre along -y.
    rng = np.random.default_rng(3)
    r, h = 0.06, 0.10
    rho = r * np.sqrt(rng.uniform(0, 1, 900))
    phi = rng.uniform(0, 2 * np.pi, 900)
    disc = np.column_stack((rho * np.cos(phi), np.zeros(900), 0.1 + rho * np.sin(phi)))
    t = rng.uniform(0, h, 300)  # from the base toward the apex
    phi = rng.uniform(-0.6, 0.6, 300) - np.pi / 2  # the strip seen below the disc
    ring = r * (1 - t / h)
    side = np.column_stack((ring * np.cos(phi), t, 0.1 + ring * np.sin(phi)))
    points = np.vstack((disc, side)) + rng.normal(0, 0.001, (1200, 3))
    fit = fit_cluster(points, rng=np.random.default_rng(0))
    assert fit is not None and fit.primitive.kind is ShapeKind.CONE
    assert fit.primitive.height == pytest.approx(h, abs=0.01)
    assert fit.primitive.radius == pytest.approx(r, abs=0.008)
    apex = fit.primitive.apex
    assert apex is not None and np.linalg.norm(np.asarray(apex) - (0, h, 0.1)) < 0.015


def test_a_cone_from_more_than_three_points_per_hypothesis():
    model = ConeModel(sample_size=5)
    apex, axis, theta = np.array([0.0, 0.0, 0.3]), np.array([0.0, 0.0, -1.0]), 0.4
    rng = np.random.default_rng(1)
    k = rng.uniform(0.02, 0.2, 50)
    phi = rng.uniform(0, 2 * np.pi, 50)
    ring = np.column_stack((np.cos(phi), np.sin(phi), np.zeros(50)))
    points = apex + np.outer(k, axis) + (k * np.tan(theta))[:, None] * ring
    normals = np.cos(theta) * ring + np.sin(theta) * axis[None, :] * -1
    params, ok = model.hypotheses(points, normals, np.arange(10).reshape(2, 5))
    assert ok.all()
    assert np.allclose(params[:, :3], apex, atol=1e-9)
    assert np.allclose(params[:, 3:6], axis, atol=1e-9)
    assert np.allclose(params[:, 6], theta, atol=1e-9)


def test_upright_cone_hypotheses_from_two_points_recover_the_cone():
    from shapes.fit.models import UprightConeModel

    model = UprightConeModel(ConeModel())
    apex, theta = np.array([0.1, -0.2, 0.15]), 0.35
    phi = np.array([0.3, 2.0, 4.0])
    k = np.array([0.03, 0.08, 0.12])  # distance from the apex along the axis (down)
    ring = np.column_stack((np.cos(phi), np.sin(phi), np.zeros(3)))
    points = apex + np.outer(k, [0.0, 0.0, -1.0]) + (k * np.tan(theta))[:, None] * ring
    normals = np.cos(theta) * ring + np.sin(theta) * np.array([0.0, 0.0, 1.0])
    normals[1] *= -1  # unoriented normals are turned up
    params, ok = model.hypotheses(points, normals, np.array([[0, 1], [1, 2]]))
    assert ok.all()
    assert np.allclose(params[:, :3], apex, atol=1e-9)
    assert np.allclose(params[:, 3:6], [0.0, 0.0, -1.0])
    assert np.allclose(params[:, 6], theta)


def test_upright_cylinder_hypotheses_from_two_points_recover_the_cylinder():
    from shapes.fit.models import UprightCylinderModel

    up = np.array([0.0, 0.6, 0.8])  # a support tilted in the sensor's frame
    side = np.cross(up, [1.0, 0.0, 0.0])
    side /= np.linalg.norm(side)
    other = np.cross(up, side)
    centre, radius = np.array([0.1, -0.2, 0.15]), 0.04
    phi = np.array([0.3, 2.0, 4.0])
    ring = np.outer(np.cos(phi), side) + np.outer(np.sin(phi), other)
    points = centre + radius * ring + np.outer([0.01, 0.07, 0.12], up)
    normals = ring * np.array([[1.0], [-1.0], [1.0]])  # unoriented
    model = UprightCylinderModel(CylinderModel(), tuple(up))
    params, ok = model.hypotheses(points, normals, np.array([[0, 1], [1, 2]]))
    assert ok.all()
    np.testing.assert_allclose(params[:, 3:6], [up, up], atol=1e-12)
    np.testing.assert_allclose(params[:, 6], radius, atol=1e-12)
    for p in params:  # the point found lies on the axis
        off = centre - p[:3]
        np.testing.assert_allclose(off - (off @ up) * up, 0.0, atol=1e-12)


@pytest.mark.parametrize("refine", [False, True])
def test_ransac_returns_the_distances_its_inliers_were_drawn_from(refine):
    rng = np.random.default_rng(5)
    points = front_sphere(rng, (0, 0, 0.05), 0.05)
    points = points + rng.normal(0, 0.002, points.shape)
    model = SphereModel()
    res = ransac(model, points, np.zeros_like(points), threshold=0.007, rng=rng, refine=refine)
    assert res is not None
    expected = model.distances(res.params[None, :], points)[0]
    np.testing.assert_allclose(res.distances, expected, rtol=0, atol=1e-12)
    assert np.array_equal(res.inliers, res.distances < 0.007)


class NeverHopeless(CylinderModel):
    """The cylinder model without its shortcut: every search builds every hypothesis."""

    def hopeless(self, normals):
        return False


@pytest.mark.parametrize("preview_points", [0, 40])
def test_a_hopeless_cylinder_search_draws_what_the_full_search_draws(preview_points):
    points = np.random.default_rng(1).random((120, 3))
    up = np.tile([0.0, 0.0, 1.0], (120, 1))
    normals = up + np.random.default_rng(2).normal(0, 0.01, up.shape)  # all within a degree
    normals /= np.linalg.norm(normals, axis=1)[:, None]
    assert CylinderModel().hopeless(normals)
    after = []
    for model in (CylinderModel(), NeverHopeless()):
        rng = np.random.default_rng(3)
        kwargs = {"threshold": 0.01, "rng": rng, "preview_points": preview_points}
        assert ransac(model, points, normals, **kwargs) is None
        after.append(rng.integers(0, 2**62, 4).tolist())
    assert after[0] == after[1]  # the next search's draws are the same


def test_a_cylinder_search_is_hopeless_only_when_no_two_normals_make_an_axis():
    rng = np.random.default_rng(4)
    normals = cylinder_side(rng, (0, 0, 0), (0, 0, 1), 1.0, 0.0, n=50, arc=0.3)  # 17 degrees
    assert not CylinderModel().hopeless(normals)
    flat = np.tile([0.0, 1.0, 0.0], (50, 1))
    assert CylinderModel().hopeless(flat)
    flat[7] = (0.0, 0.0, 1.0)  # one normal across the others: one pair makes an axis
    assert not CylinderModel().hopeless(flat)
    flat[7] = (0.0, -1.0, 0.0)  # unoriented: the opposite normal is the same line
    assert CylinderModel().hopeless(flat)
    flat[7] = np.nan  # a broken normal: no shortcut, the search decides
    assert not CylinderModel().hopeless(flat)


def test_the_models_3_vector_helpers_equal_numpy_to_the_bit():
    from shapes.arrays import cross3, dot3, norm3

    rng = np.random.default_rng(6)
    a = rng.normal(size=(8, 250, 3)) * rng.uniform(1e-3, 10.0, size=(8, 250, 3))
    b = rng.normal(size=(8, 1, 3))
    assert np.array_equal(dot3(a, b), (a * b).sum(axis=2))
    assert np.array_equal(norm3(a), np.linalg.norm(a, axis=2))
    assert np.array_equal(cross3(a[0], a[1]), np.cross(a[0], a[1]))
