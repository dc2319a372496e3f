"""Fitting one cluster: every model is fitted, then one is chosen by the rule below.

Shape-choice rule (replaces PITT's "most raw inliers, cone if ≥ 0.9 · cylinder")
-------------------------------------------------------------------------------
Each candidate is scored on the cluster's points by a *truncated quadratic* (MSAC) cost,
``mean(min(d / T, 1)²)`` with one common threshold ``T = selection_threshold_m`` for all
models, where ``d`` is the distance of a point to the candidate's *whole visible surface*:

- sphere: the sphere;
- cylinder: the lateral surface **and its two end discs** (a cylinder's flat top is part of the
  cylinder, so it no longer hands the cluster to "plane");
- cone: the lateral surface;
- plane: the union of up to ``max_planes`` planes found one after another, each holding at least
  ``min_plane_share`` of the points (a box shows up to three faces); each point then goes to
  its nearest face and every face is refitted, so box edges do not tilt the faces.

The same surfaces drive the search: cylinder hypotheses are scored with their end discs, so a
dominant flat top cannot pull RANSAC to a wide cylinder lying on its side; sphere and cylinder
radii are bounded by ``max_radius_per_extent`` times the cluster's size (a larger radius only
imitates a slightly bent flat face); cylinders and cones get at least ``min_iterations``
hypotheses, each batch ranked first on ``preview_points`` points. On a support, cylinders and
cones also get two-point hypotheses with the support's normal for an axis
(``upright_cylinder_iterations``, ``upright_cone_iterations``): standing is the commonest pose
of a thing on a table, and noisy normals tilt the free hypotheses' axes (seen from far, the
free search may find only a lying cylinder; the standing hypotheses draw from a generator of
their own, so the other searches' draws stay as they were). Cones get one more source of
hypotheses, as noisy normals spoil the free three-point ones: for each of the first two planes
holding ``min_base_share`` of the points, the cone whose base is that plane (a lying or leaning
cone showing its base). Only the curved candidates
within ``refine_margin`` of the best cost are refined by least squares (Levenberg-Marquardt on
the inliers; a cylinder on its lateral band away from the discs), and a refinement is kept only
if it lowers the cost and respects the limits.

Cones around a cylinder: when the refined cylinder costs less than every cone, does not stand on
the support and is not seen under coarse depth (the selection threshold less than
``coarse_standing_share`` times its radius), two more cone candidates are fitted by least squares
to its inliers (``cone_around_points`` of them, ``cone_around_iterations`` steps), starting from
the narrowest cones (``min_cone_half_angle_deg``) on its axis, one narrowing each way; one
replaces the cone if it ranks better, the oblique penalty included. A narrow leaning cone's free
three-point hypotheses often miss it (their apex comes from three noisy normals), and a cylinder
is then the best curved fit; a cylinder around such a cone lies close to the cone's own axis.

The lowest cost wins; candidates within ``tie_margin`` of it are resolved in the order sphere,
cylinder, cone, plane (fewest parameters first). Between a cylinder and a cone standing on the
support whose costs lie within ``taper_margin`` of each other, the points decide instead: a cone
is an object whose side narrows upwards by more than ``taper_sigmas`` times the measured spread
of the side (:func:`standing_taper`), since under range noise the costs of the two no longer
tell them apart. When the support is known, a cylinder or cone
whose axis could not rest on it (neither standing nor lying, within ``resting_tolerance_deg``)
pays ``oblique_penalty`` against the other curved models: a tilted cylinder is what a partly
hidden cone looks like, not a thing found on tables. The penalty never hands a cluster to the
planes: the best curved model meets them on its own cost (a leaning cone stays a cone). Unlike
an inlier count, the cost rewards a model for how *closely* the points fit, not just whether
they fall within a loose band: a flat patch of a sphere or a band of a cone that lies within a
few millimetres of a plane or a cylinder still costs more than the surface that explains every
point at noise level.

Spheres along the rays
----------------------
Range noise moves each point along the sensor's ray, not along the surface's normal, and far
from the sensor it is as large as a small sphere's bulge: by the distance to each surface, a
cylinder or cone folded through the cluster then costs less than the sphere, even the true one.
When the sensor's centre is known (``viewpoint``), the sphere is weighed against the model the
rule above chooses without it, when that is a cylinder or cone and the sphere costs at most
``ray_gate`` more than it: each is scored by the error along each point's ray to the first
surface the ray meets (:mod:`shapes.fit.ray`: its range minus the range at which its ray first
meets the candidate's closed surface; a ray that misses it costs the most), after refining it
under that error (the sphere from its fit and from its outline, the cylinder or cone from its
fit and, standing, with the support's normal for an axis; the cheaper start kept). The other
curved model (the cone against a cylinder, the cylinder against a cone) is refined and scored the
same way, since the rule's rival may be the one that refines worse. The sphere is chosen when it
costs no more than the cheaper of the two plus ``tie_margin``, and then meets the planes
with the lower of the two costs (by the distance to the surface); otherwise the sphere is out.
The rival is not refitted otherwise: the cylinder/cone choice stays the rule's own.

Standing under coarse depth
---------------------------
When the depth noise is comparable to a thing's radius (the selection threshold, which grows
with the cluster's noise, at least ``coarse_standing_share`` of the radius of the best standing
cylinder hypothesis, before and after its refinement), the distances to the surface no longer
tell a standing cylinder from one lying or leaning: quantised depths put the points on sheets
square to the sensor's rays, and a wide cylinder whose end disc faces the sensor explains those
sheets better than the true narrow one standing. There, when the support is known and the free
search's cylinder does not stand, the best standing hypothesis (refined by least squares, still
standing) takes its place if it costs at most ``coarse_standing_margin`` more, and meets the
other models with the lower of the two costs. At the lowest threshold (8 mm, low noise) only
standing radii of 2 cm or less qualify.

A pointed outline under coarse depth
------------------------------------
Range noise moves a point along its ray; its pixel stays where it was, so the cluster's outline
in the image stays sharp when the depths are coarse (:mod:`shapes.fit.outline`: each point moved
along its ray onto the plane across its median point's ray, its rows square to the support's
normal). An outline that closes to a point at its top (its rows over its top half width filling
less than ``outline_pointed_fullness`` of its width) is a cone's, apex up: a sphere's outline is
a circle and a standing cylinder's a rectangle under the ellipse of its top. So when the
viewpoint and the support are known, the rule above chooses a sphere or a cylinder, a cone is in
the running, the selection threshold is at least ``outline_coarse_share`` of half the outline's
width and the outline has at least ``outline_min_rows`` rows, the sphere and the standing
cylinder leave the running, unless the middles of the outline's top rows stray by more than
``outline_max_lean`` of its width from those of its widest (a part of a thing, one side cut off
by a split or an occluder: its shape says nothing of the whole). The choice is then made again
without them. The outline is read only where the threshold is at least half that share of the
larger of the two models' radii (a whole one's outline is about as wide as the model): reading
it costs a k-d tree over the cluster's points.

Standing and widening upwards
-----------------------------
A round thing that widens upwards (a paper cup, a flower pot) has no model of its own: standing
cones point up. Three planes bent round its visible arc then cost less than a cylinder, whose
side misses the bottom and the rim. So, when the rule above would choose the planes and the
support is known, the side's profile is read (:func:`shapes.fit.profile.side_profile`: the
radius about the support's normal through the side's circle, a straight line of the height);
when it widens upwards by more than ``taper_sigmas`` times its spread (at least
``taper_min_spread_m``), the standing cylinder of its mid-side radius is scored on the points
moved along their radii by the profile's excess at their height, and that cost, when lower,
becomes the cylinder's. A side that narrows upwards is the cone's, and is left to it. So no cone
stands on its tip: a cone candidate whose axis lies within ``upright_tolerance_deg`` of the
support's normal and which widens upwards (its apex at the bottom) is never kept, from any of
the searches above; such a thing is the cylinder's, taper taken out or not.

A lying cylinder rests on something
-----------------------------------
A cylinder that does not stand is a body lying or leaning on the support, or on something else
in its cluster: no part of it lies under the support. The bend of a broad face seen from above
(a bottle flat on its broad side) is fitted best by the top of a wide cylinder whose axis lies
in the table. So a cylinder candidate whose axis lies farther than ``upright_tolerance_deg``
from the support's normal, and whose finite body (its axis between the points' ends, as the
primitive is built) reaches under the support deeper than ``max_sink_thresholds`` times the
selection threshold (three times the depth noise, at least 8 mm), is never output: when the
shape-choice rule chooses it, the choice is made again without it, and the next cheapest model
takes its place. It is judged on the choice, not on every candidate of the searches as a cone on
its tip is: the searches build on their candidates (a refinement, the cones around a cylinder),
and refusing the sunk ones there cost two simulated leaning or lying objects.

Rings and outlines
------------------
A depth camera spreads a nearer surface's depth a few pixels past its edge (the Kinect) or
returns mixed depths there, so the points on the fringe of a cluster's outline lie off the
object's surface, outside it; a ring's or an open container's top adds the inside seen through
it. Both pull every fit towards a wider model. So when the support is known, one more standing
cylinder is tried after the refinements: the circle of the side wall alone
(:func:`shapes.fit.fringe.side_wall_circle`: the points more than ``side_wall_cut_m`` under the
top, the circle fitted again without the side points off it, as the ground truth is measured).
With a viewpoint, its cost leaves out the sample's points on the outline's fringe
(:func:`shapes.fit.fringe.fringe`, ``fringe_cells`` cells of ``fringe_cell_steps`` image steps)
that lie outside it and farther than the selection threshold from it. It takes the cylinder's
place when that cost is below the cylinder's by more than ``tie_margin`` and not above the
planes' by more (else it changes nothing), and is not refined (on every point, the fringe would
pull it wider again). No other candidate leaves any point out.

Faces charged for their parameters
----------------------------------
Up to ``max_planes`` faces fitted one after another have three free parameters each (a
direction and an offset), against a cylinder's five or a sphere's four: three faces bent round
a can's visible arc follow it about as closely as the can's own cylinder, and under coarse
depth a little more closely, since each face takes a terrace of the quantised depths. So when
the best curved model meets the planes, each pays for its free parameters the Bayesian
information criterion's charge on the cost's scale (``parameter_charge`` times
``ln(n) / (noise_factor² n)`` a parameter, ``n`` the points scored: the cost of a point is its
squared error over ``noise_factor²`` noise variances where the threshold is set by the noise,
so this is BIC divided by ``noise_factor² n``). On 300 points three faces pay 0.0085 more than
a cylinder, two faces 0.0021 more, one face 0.0042 less: it decides only near ties, and a
single flat face wins them more easily than before.

Heights are measured to the support: when a cylinder's or cone's axis is within
``upright_tolerance_deg`` of the support normal and its lowest points lie within
``snap_distance_m`` of the support, the base is put on the support plane. The segmentation has
to drop the bottom centimetre of each object with the table; this gives it back.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field, replace

import numpy as np
import open3d as o3d
from scipy.spatial import ConvexHull, QhullError, cKDTree

from shapes.arrays import column_max, column_min, column_span, norm3, percentiles
from shapes.fit._ransac import Model, levenberg_marquardt, ransac, refine_if_better
from shapes.fit.fringe import fringe, side_wall_circle
from shapes.fit.information import parameter_charges
from shapes.fit.models import (
    ConeModel,
    CylinderModel,
    Mask,
    PlaneModel,
    SphereModel,
    UprightConeModel,
    UprightCylinderModel,
)
from shapes.fit.outline import outline_rows, pointed, top_lean
from shapes.fit.profile import cylinder_without_taper, side_profile
from shapes.fit.ray import RayModel, fit_ends, ray_cost, refine_on_rays, sphere_from_outline
from shapes.normals import patch_normals
from shapes.types import FloatArray, Primitive, ShapeKind, SupportPlane, vec3

__all__ = [
    "ClusterFit",
    "FitParams",
    "bounded",
    "estimate_normals",
    "fit_cluster",
    "normals_at",
    "pitt_choice",
]

ORDER = (ShapeKind.SPHERE, ShapeKind.CYLINDER, ShapeKind.CONE, ShapeKind.PLANE)


@dataclass(frozen=True)
class FitParams:
    """Parameters of :func:`fit_cluster`. RANSAC thresholds are PITT's defaults (metres)."""

    sphere_threshold_m: float = 0.007
    cylinder_threshold_m: float = 0.008
    cone_threshold_m: float = 0.0055
    plane_threshold_m: float = 0.007
    min_radius_m: float = 0.005
    max_radius_m: float = 0.5
    max_radius_per_extent: float = 0.67
    min_cone_half_angle_deg: float = 10.0
    max_cone_half_angle_deg: float = 80.0
    max_iterations: int = 1000
    min_iterations: int = 128
    preview_points: int = 100
    cone_sample_points: int = 3
    upright_cone_iterations: int = 128
    upright_cylinder_iterations: int = 128
    min_base_share: float = 0.25
    max_fit_points: int = 300
    normal_neighbours: int = 30
    selection_threshold_m: float = 0.008
    max_planes: int = 3
    min_plane_share: float = 0.05
    max_plane_iterations: int = 100
    tie_margin: float = 0.01
    resting_tolerance_deg: float = 10.0
    oblique_penalty: float = 0.03
    refine_margin: float = 0.05
    upright_tolerance_deg: float = 20.0
    snap_distance_m: float = 0.03
    noise_factor: float = 3.0
    taper_margin: float = 0.03
    taper_sigmas: float = 0.35
    taper_upright_deg: float = 30.0
    taper_min_spread_m: float = 0.002
    taper_cut_share: float = 0.4
    ray_iterations: int = 8
    ray_gate: float = 0.03
    """With a viewpoint: how much more than its rival (by the distance to the surface) a sphere
    may cost and still be weighed against it along the rays; ``ray_iterations``: the
    Levenberg-Marquardt steps of each refinement along them."""
    cone_around_points: int = 100
    cone_around_iterations: int = 6
    """Cones around a cylinder (module docstring): the cylinder's inliers they are fitted on,
    at most, and the Levenberg-Marquardt steps of each fit."""
    coarse_standing_margin: float = 0.05
    coarse_standing_share: float = 0.4
    """Standing under coarse depth (module docstring): how much more than the free cylinder a
    standing one may cost and still be chosen, when the selection threshold is at least
    ``coarse_standing_share`` of its radius."""
    outline_coarse_share: float = 0.4
    outline_pointed_fullness: float = 0.6
    outline_max_lean: float = 0.1
    outline_min_rows: int = 8
    """A pointed outline under coarse depth (module docstring): the selection threshold at
    least ``outline_coarse_share`` of half the outline's width, its top half width filled
    below ``outline_pointed_fullness`` (:func:`shapes.fit.outline.top_fullness`), its top's
    rows centred within ``outline_max_lean`` of its width (:func:`shapes.fit.outline.top_lean`)
    and at least ``outline_min_rows`` rows."""

    max_sink_thresholds: float = 1.0
    """A lying cylinder rests on something (module docstring): how deep under the support, in
    selection thresholds, a cylinder that does not stand may reach and still be output."""
    fringe_cells: int = 3
    fringe_cell_steps: float = 1.5
    """The outline's fringe (module docstring, "Rings and outlines"): its width in cells of
    ``fringe_cell_steps`` of the image's steps between the cluster's points
    (:func:`shapes.fit.fringe.fringe`); 0 cells scores every point."""
    parameter_charge: float = 1.0
    """The planes against the curved model (module docstring, "Faces charged for their
    parameters"): each candidate's cost at that meeting is raised by this times its free
    parameters times ``ln(n) / (noise_factor² n)`` for ``n`` points scored (the Bayesian
    information criterion's charge on the cost's scale); 0 charges nothing."""
    side_wall_cut_m: float = 0.015
    side_wall_band_m: float = 0.003
    """The side wall's cylinder (module docstring): how far under the top the side wall starts,
    and the least band about its circle within which a side point is kept
    (:func:`shapes.fit.fringe.side_wall_circle`); a cut of 0 tries no such cylinder."""

    def for_noise(self, sigma_m: float) -> FitParams:
        """These parameters with every distance threshold raised to at least
        ``noise_factor * sigma_m`` (the depth noise at the cluster's range); unchanged when the
        noise is low enough for the defaults.

        >>> FitParams().for_noise(0.005).selection_threshold_m
        0.015
        """
        floor = self.noise_factor * sigma_m
        names = (
            "sphere_threshold_m",
            "cylinder_threshold_m",
            "cone_threshold_m",
            "plane_threshold_m",
            "selection_threshold_m",
        )
        changes = {n: round(max(getattr(self, n), floor), 6) for n in names}
        return replace(self, **changes)


@dataclass(frozen=True, eq=False)
class ClusterFit:
    """The chosen primitive, every candidate's cost and PITT's inlier counts (for comparison)."""

    primitive: Primitive
    costs: dict[ShapeKind, float] = field(default_factory=dict)
    pitt_counts: dict[ShapeKind, int] = field(default_factory=dict)


def pitt_choice(counts: dict[ShapeKind, int]) -> ShapeKind | None:
    """PITT's rule (§4.12 of the reference): raw inlier counts, cone first if ≥ 0.9 · cylinder.

    >>> pitt_choice({ShapeKind.SPHERE: 10, ShapeKind.CYLINDER: 50,
    ...              ShapeKind.CONE: 46, ShapeKind.PLANE: 20})
    <ShapeKind.CONE: 'Cone'>
    """
    p, s = counts.get(ShapeKind.PLANE, 0), counts.get(ShapeKind.SPHERE, 0)
    cy, co = counts.get(ShapeKind.CYLINDER, 0), counts.get(ShapeKind.CONE, 0)
    if p == s == cy == co == 0:
        return None
    if co >= p and co >= s and co >= 0.9 * cy:
        return ShapeKind.CONE
    if cy >= p and cy >= co and cy >= s:
        return ShapeKind.CYLINDER
    if p >= co and p >= s and p >= cy:
        return ShapeKind.PLANE
    if s >= p and s >= co and s >= cy:
        return ShapeKind.SPHERE
    return None


def normals_at(points: FloatArray, at: FloatArray, neighbours: int) -> FloatArray:
    """Unoriented unit normals at the points ``at``, each from its ``neighbours`` nearest
    points of ``points`` (the smallest principal axis of their covariance).

    >>> flat = np.column_stack((np.random.default_rng(0).random((50, 2)), np.zeros(50)))
    >>> np.abs(normals_at(flat, flat[:2], 10)).round(6).tolist()
    [[0.0, 0.0, 1.0], [0.0, 0.0, 1.0]]
    """
    # A tree built for one query: the unbalanced build is the faster, the neighbours the same.
    tree = cKDTree(points, balanced_tree=False, compact_nodes=False)
    return patch_normals(points, tree.query(at, k=neighbours)[1])


def estimate_normals(points: FloatArray, neighbours: int) -> FloatArray:
    """Unoriented unit normals from the ``neighbours`` nearest points (open3d)."""
    cloud = o3d.geometry.PointCloud(o3d.utility.Vector3dVector(points))
    cloud.estimate_normals(o3d.geometry.KDTreeSearchParamKNN(neighbours))
    return np.asarray(cloud.normals, dtype=np.float64)


def _axial(params: FloatArray, points: FloatArray) -> tuple[FloatArray, FloatArray]:
    v = points - params[:3]
    t = v @ params[3:6]
    rho = norm3(v - np.outer(t, params[3:6]))
    return t, rho


def _can_rest(kind: ShapeKind, params: FloatArray, support: SupportPlane, fp: FitParams) -> bool:
    """Whether a cylinder or cone could rest on the support: standing (axis along the
    support normal) or lying on its side (cylinder axis parallel to the support, cone tilted by
    90 degrees minus its half angle), within ``resting_tolerance_deg``."""
    tilt = math.degrees(math.acos(min(1.0, abs(float(params[3:6] @ np.asarray(support.normal))))))
    lying = 90.0 if kind is ShapeKind.CYLINDER else 90.0 - math.degrees(float(params[6]))
    tol = fp.resting_tolerance_deg
    return tilt <= tol or abs(tilt - lying) <= tol


def _cost(d: FloatArray, threshold: float) -> float:
    return float(np.mean(np.minimum(d / threshold, 1.0) ** 2))


def _orient_up(axis: FloatArray, support: SupportPlane | None, tol_deg: float) -> bool:
    """Whether the axis is upright with respect to the support."""
    if support is None:
        return False
    return abs(float(axis @ np.asarray(support.normal))) >= math.cos(math.radians(tol_deg))


def _build_cylinder(
    params: FloatArray, points: FloatArray, support: SupportPlane | None, fp: FitParams
) -> Primitive:
    p0, axis, r = params[:3], params[3:6].copy(), float(params[6])
    upright = _orient_up(axis, support, fp.upright_tolerance_deg)
    if support is not None and float(axis @ np.asarray(support.normal)) < 0:
        axis = -axis
    t, rho = _axial(np.concatenate((p0, axis, [r])), points)
    lo, hi = percentiles(t, [0.5, 99.5])
    cap = (t > hi - 2 * fp.selection_threshold_m) & (rho < 0.8 * r)
    if cap.sum() >= 10:
        hi = float(np.median(t[cap]))
    if upright and support is not None:
        n = np.asarray(support.normal)
        t_plane = -float(n @ p0 + support.offset) / float(n @ axis)
        if lo - t_plane < fp.snap_distance_m:
            lo = t_plane
    base = p0 + lo * axis
    return Primitive(
        ShapeKind.CYLINDER,
        centre=vec3(p0 + (lo + hi) / 2 * axis),
        axis=vec3(axis),
        radius=r,
        height=hi - lo,
        point_on_axis=vec3(base),
    )


def _build_cone(
    params: FloatArray, points: FloatArray, support: SupportPlane | None, fp: FitParams
) -> Primitive:
    apex, axis, theta = params[:3], params[3:6], float(params[6])
    k = (points - apex) @ axis
    height = percentiles(k, [99.5])[0]
    if support is not None and _orient_up(axis, support, fp.upright_tolerance_deg):
        n = np.asarray(support.normal)
        denom = float(n @ axis)
        k_plane = -float(n @ apex + support.offset) / denom
        if k_plane > 0 and k_plane - height < fp.snap_distance_m:
            height = k_plane
    return Primitive(
        ShapeKind.CONE,
        centre=vec3(apex + 0.75 * height * axis),
        axis=vec3(axis),
        radius=height * math.tan(theta),
        height=height,
        apex=vec3(apex),
    )


def _stands_on_its_tip(params: FloatArray, support: SupportPlane | None, fp: FitParams) -> bool:
    """Whether a cone stands (its axis within ``upright_tolerance_deg`` of the support's
    normal) with its apex down: it widens upwards from a tip at or under the support.

    >>> table = SupportPlane((0.0, 0.0, 1.0), 0.0)
    >>> down = np.array([0.0, 0.0, 0.3, 0.0, 0.0, -1.0, 0.3])  # apex up, widening downwards
    >>> up = np.array([0.0, 0.0, -0.08, 0.0, 0.0, 1.0, 0.3])  # apex under the table
    >>> _stands_on_its_tip(down, table, FitParams()), _stands_on_its_tip(up, table, FitParams())
    (False, True)
    """
    if support is None or not _orient_up(params[3:6], support, fp.upright_tolerance_deg):
        return False
    return float(params[3:6] @ np.asarray(support.normal)) > 0


def _sunk_in_support(cylinder: Primitive, support: SupportPlane | None, fp: FitParams) -> bool:
    """Whether a cylinder that does not stand (its axis farther than ``upright_tolerance_deg``
    from the support's normal) reaches under the support deeper than ``max_sink_thresholds``
    selection thresholds: the lowest point of its body (the lower end of its axis segment, less
    the radius times the sine of its tilt) lies that far under the support. False with no
    support or for a standing cylinder.

    >>> table = SupportPlane((0.0, 0.0, 1.0), 0.0)
    >>> def lying(axis_height_m: float) -> Primitive:
    ...     return Primitive(ShapeKind.CYLINDER, centre=(0.0, 0.0, axis_height_m),
    ...                      axis=(1.0, 0.0, 0.0), radius=0.05, height=0.2)
    >>> _sunk_in_support(lying(0.048), table, FitParams())  # resting, 2 mm in: within the noise
    False
    >>> _sunk_in_support(lying(0.003), table, FitParams())  # its axis in the table
    True
    """
    assert cylinder.axis is not None and cylinder.radius is not None
    if support is None or _orient_up(np.asarray(cylinder.axis), support, fp.upright_tolerance_deg):
        return False
    n, axis, centre = (
        np.asarray(support.normal),
        np.asarray(cylinder.axis),
        np.asarray(cylinder.centre),
    )
    half = 0.5 * (cylinder.height or 0.0) * axis
    ends = support.signed_distance(np.array((centre - half, centre + half)))
    sine = math.sqrt(max(0.0, 1.0 - float(axis @ n) ** 2))
    lowest = float(ends.min()) - cylinder.radius * sine
    return lowest < -fp.max_sink_thresholds * fp.selection_threshold_m


def _build_plane(params: FloatArray, points: FloatArray, inliers: FloatArray) -> Primitive:
    n = params[:3].copy()
    centre = inliers.mean(axis=0)
    outward = float(n @ (centre - points.mean(axis=0)))
    if outward < -1e-4 or (abs(outward) <= 1e-4 and n[2] < 0):
        n = -n
    return Primitive(
        ShapeKind.PLANE, centre=vec3(centre), axis=vec3(n), hessian_offset=float(-n @ centre)
    )


def _cone_on_base(plane: FloatArray, points: FloatArray, threshold: float) -> FloatArray | None:
    """Cone parameters (apex, unit axis from the apex, half angle) for a cone whose flat base is
    ``plane``: the axis is the plane's normal, turned away from the other points; the centre and
    radius come from a circle through the outline (2-D convex hull) of the points on the plane,
    which holds even when the disc is partly hidden (the cut is a chord of the same circle); the
    height is the median over the other points of ``t / (1 - rho / R)`` (a point at height t
    above the base, rho from the axis). None when the points do not make such a cone."""
    n, offset = plane[:3], float(plane[3])
    height = points @ n + offset
    on = np.abs(height) < threshold / 2  # the noise is about a third of the threshold
    if on.sum() < 10 or (~on).sum() < 10:
        return None
    up = n if float(np.median(height[~on])) > 0 else -n
    helper = np.array([1.0, 0.0, 0.0]) if abs(up[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    e1 = np.cross(up, helper)
    e1 /= np.linalg.norm(e1)
    e2 = np.cross(up, e1)
    flat = np.column_stack((points[on] @ e1, points[on] @ e2))
    try:
        rim = flat[ConvexHull(flat).vertices]
    except QhullError:
        return None
    if len(rim) < 4:
        return None
    a = np.column_stack((2 * rim, np.ones(len(rim))))
    (cu, cv, c0), *_ = np.linalg.lstsq(a, (rim * rim).sum(axis=1), rcond=None)
    radius = math.sqrt(max(c0 + cu * cu + cv * cv, 0.0))
    base = cu * e1 + cv * e2 - offset * n  # the circle's centre, on the plane (n is unit)
    rel = points[~on] - base
    t = rel @ up
    rho = norm3(rel - np.outer(t, up))
    ok = (t > threshold) & (rho < 0.95 * radius)
    if radius <= 0 or ok.sum() < 5:
        return None
    h = float(np.median(t[ok] / (1 - rho[ok] / radius)))
    if not math.isfinite(h) or h <= 0:
        return None
    return np.concatenate((base + h * up, -up, [math.atan2(radius, h)]))


def _cones_around(
    cylinder: FloatArray,
    points: FloatArray,
    inliers: Mask,
    model: ConeModel,
    *,
    max_points: int,
    iterations: int,
) -> list[FloatArray]:
    """Cones fitted by least squares (``iterations`` Levenberg-Marquardt steps, on at most
    ``max_points`` of the cylinder's ``inliers`` taken at an even stride) from the two narrowest
    cones (``model.min_half_angle``) on the cylinder's axis, one narrowing each way, each as wide
    as the cylinder at the inliers' median position along the axis. Empty with fewer than 10
    inliers; the cones may lie outside the model's limits."""
    on = points[inliers]
    if len(on) < 10:
        return []
    on = on[:: -(-len(on) // max_points)]  # an even stride keeps the spread
    p0, axis, r = cylinder[:3], cylinder[3:6], float(cylinder[6])
    middle = p0 + float(np.median((on - p0) @ axis)) * axis
    reach = r / math.tan(model.min_half_angle)  # from the apex to where the radius is r
    cones = []
    for way in (axis, -axis):
        start = np.concatenate((middle - reach * way, way, [model.min_half_angle]))
        x = levenberg_marquardt(lambda p: model.residuals(p, on), start, iterations=iterations)
        cones.append(np.concatenate((x[:3], x[3:6] / np.linalg.norm(x[3:6]), x[6:])))
    return cones


def standing_taper(
    points: FloatArray, support: SupportPlane, cut_m: float
) -> tuple[float, float] | None:
    """How much an object standing on ``support`` narrows from the bottom to the top of its
    visible side, and the spread of its side about that straight profile (both in metres).

    The side is the points lower than ``cut_m`` under the object's top (the top, a cylinder's
    flat end, is left out); the axis is the support's normal through the centre of the circle
    fitted to the side points (algebraic least squares); the radius is then fitted as a
    straight line of the height. Returns ``(drop, spread)``: the radius lost over the side's
    height (positive when it narrows upwards, as a standing cone) and the robust standard
    deviation of the radii about the line; None with fewer than 20 side points.

    >>> angle = np.linspace(-1.2, 1.2, 40)
    >>> h = np.repeat(np.linspace(0.0, 0.1, 20), 40)
    >>> r = 0.05 - 0.3 * h  # a cone narrowing by 3 cm over 10 cm
    >>> a = np.tile(angle, 20)
    >>> cone = np.column_stack((r * np.sin(a), -r * np.cos(a), h))
    >>> drop, spread = standing_taper(cone, SupportPlane((0.0, 0.0, 1.0), 0.0), 0.01)
    >>> round(drop, 3), round(spread, 3)
    (0.024, 0.007)
    """
    profile = side_profile(points, support, cut_m)
    return None if profile is None else (profile.drop_m, profile.spread_m)


def _without_taper(
    sample: FloatArray,
    support: SupportPlane,
    fp: FitParams,
    model: CylinderModel,
) -> tuple[FloatArray, FloatArray] | None:
    """The standing cylinder of a thing whose side widens upwards, and the distances of
    ``sample`` to it with the taper taken out (:func:`shapes.fit.profile.cylinder_without_taper`;
    module docstring, "Standing and widening upwards"); None when the side does not widen by
    more than ``taper_sigmas`` times its spread, or the radius is out of the model's limits.
    The side is measured on the ``sample``: the cost, not the profile, decides, and on a large
    cluster the profile on all the points cost twice as much."""
    profile = side_profile(sample, support, fp.selection_threshold_m)
    if profile is None:
        return None
    if -profile.drop_m <= fp.taper_sigmas * max(profile.spread_m, fp.taper_min_spread_m):
        return None
    params, d = cylinder_without_taper(sample, profile, support, model)
    return (params, d) if model.within_limits(params) else None


def _outside(cylinder: FloatArray, points: FloatArray) -> Mask:
    """Which ``points`` lie farther from the cylinder's axis than its side."""
    return np.asarray(_axial(cylinder, points)[1] > cylinder[6])


def _side_wall_cylinder(
    sample: FloatArray, support: SupportPlane, fp: FitParams, model: Model
) -> tuple[FloatArray, FloatArray] | None:
    """The standing cylinder through the side wall's circle (module docstring, "Rings and
    outlines") and the distances of ``sample`` to it; None when the side wall has too few
    points or the radius is out of the model's limits."""
    circle = side_wall_circle(
        sample, support, cut_m=fp.side_wall_cut_m, min_band_m=fp.side_wall_band_m
    )
    if circle is None:
        return None
    foot, radius, _ = circle
    params = np.concatenate((foot, np.asarray(support.normal, dtype=np.float64), [radius]))
    if not model.within_limits(params):
        return None
    return params, model.distances(params[None, :], sample)[0]


def _choose(
    costs: dict[ShapeKind, float],
    fitted: dict[ShapeKind, FloatArray],
    support: SupportPlane | None,
    fp: FitParams,
    points: FloatArray | None = None,
    sphere_on_rays: bool | None = None,
    charges: dict[ShapeKind, float] | None = None,
) -> ShapeKind:
    """The shape by the rule of the module docstring. The oblique penalty only ranks the curved
    models among themselves (a tilted cylinder is what a partly hidden cone looks like); the
    best curved model then meets the planes on its own cost, so a leaning cone that fits better
    than the planes stays a cone.

    Cylinder or cone, standing (either candidate's axis within ``taper_upright_deg`` of the
    support's normal): when their costs (without
    the oblique penalty) lie within ``taper_margin`` of each other, the costs cannot tell them
    apart (under range noise a cone's extra parameter fits the noise,
    and a narrow cone is a cylinder within the threshold). The points decide (``points``: all
    the cluster's, not the fit sample, as the measured drop of a cylinder's side is noise that
    shrinks with the square root of their number): a cone narrows
    upwards, so it is a cone when its side's radius drops by more than ``taper_sigmas`` times
    the spread of the side about its profile (:func:`standing_taper`: the measured residual,
    taken as at least ``taper_min_spread_m`` so that a noiseless side does not make every
    tenth of a millimetre significant); else a cylinder.

    ``sphere_on_rays`` (from the rays, when the viewpoint is known and the rule without the
    sphere chose a cylinder or cone): None, the sphere competes on its cost as above; False,
    it is not chosen; True, it takes the curved model's place and meets the planes with the
    lower of its own cost and that model's.

    ``charges``: what each kind pays for its parameters when the best curved model meets the
    planes (:func:`shapes.fit.information.parameter_charges`); nothing when None."""
    charge = charges or {}
    choice = {k: c for k, c in costs.items() if k is not ShapeKind.PLANE}
    if sphere_on_rays is not None:
        choice.pop(ShapeKind.SPHERE, None)
    if support is not None:
        for kind in (ShapeKind.CYLINDER, ShapeKind.CONE):
            if kind in choice and not _can_rest(kind, fitted[kind], support, fp):
                choice[kind] += fp.oblique_penalty
    candidates = {ShapeKind.PLANE: costs[ShapeKind.PLANE]} if ShapeKind.PLANE in costs else {}
    curved: ShapeKind | None = None
    if choice:
        best = min(choice.values())
        curved = next(k for k in ORDER if k in choice and choice[k] <= best + fp.tie_margin)
        if points is not None and support is not None:
            curved = _by_taper(curved, costs, fitted, support, fp, points)
    if curved is not None:
        candidates[curved] = costs[curved]
    if sphere_on_rays and ShapeKind.SPHERE in costs:
        # The sphere explains the points along the rays at least as well as the rival: it
        # meets the planes with the lower of the two costs.
        rival = candidates.pop(curved, np.inf) if curved is not None else np.inf
        curved = ShapeKind.SPHERE
        candidates[curved] = min(costs[curved], rival)
    candidates = {k: c + charge.get(k, 0.0) for k, c in candidates.items()}
    best = min(candidates.values())
    return next(k for k in ORDER if k in candidates and candidates[k] <= best + fp.tie_margin)


def _by_taper(
    curved: ShapeKind,
    costs: dict[ShapeKind, float],
    fitted: dict[ShapeKind, FloatArray],
    support: SupportPlane,
    fp: FitParams,
    points: FloatArray,
) -> ShapeKind:
    """Cylinder against cone for an object standing on the support (see :func:`_choose`)."""
    pair = (ShapeKind.CYLINDER, ShapeKind.CONE)
    if curved not in pair or not all(k in costs for k in pair):
        return curved
    if abs(costs[ShapeKind.CYLINDER] - costs[ShapeKind.CONE]) > fp.taper_margin:
        return curved
    if not any(_orient_up(fitted[k][3:6], support, fp.taper_upright_deg) for k in pair):
        return curved
    # The top (a cylinder's flat end, spread by the noise over about the threshold) is cut
    # off, but never more than a share of the visible height: far away the threshold may be
    # as tall as the part of the object in view, and the side left would show no slope.
    height = points @ np.asarray(support.normal, dtype=np.float64) + support.offset
    top, bottom = percentiles(height, [99, 1])
    span = top - bottom
    cut = min(fp.selection_threshold_m, fp.taper_cut_share * span)
    taper = standing_taper(points, support, cut)
    if taper is None:
        return curved
    drop, spread = taper
    spread = max(spread, fp.taper_min_spread_m)
    return ShapeKind.CONE if drop > fp.taper_sigmas * spread else ShapeKind.CYLINDER


_HEIGHT_PER_DIAGONAL = 2.0
"""An object seen with up to half of its length hidden still passes :func:`bounded`."""


def bounded(
    primitive: Primitive,
    points: FloatArray,
    *,
    margin_m: float,
    box: tuple[FloatArray, FloatArray] | None = None,
) -> bool:
    """Whether a primitive stays within its own points: its radius no longer than the diagonal
    of their bounding box (plus ``margin_m``), its height no longer than ``_HEIGHT_PER_DIAGONAL``
    times that (the part of an object hidden behind another, or a cone's tip, lies past the
    points), its centre inside that box grown by ``margin_m`` and, for a curved primitive, by its
    radius (the centre of a sphere or a can lies behind the surface the sensor sees).

    >>> pts = np.array([[0.0, 0, 0], [0.1, 0, 0], [0, 0.1, 0], [0, 0, 0.1]])
    >>> ball = Primitive(ShapeKind.SPHERE, centre=(0.05, 0.05, 0.05), radius=0.05)
    >>> bounded(ball, pts, margin_m=0.01), bounded(replace(ball, radius=2.0), pts, margin_m=0.01)
    (True, False)

    ``box``: the points' ``(min, max)`` corners when the caller has them already (a cluster's
    candidates are all held to the same box).
    """
    lo, hi = box if box is not None else (column_min(points), column_max(points))
    diagonal = float(np.linalg.norm(hi - lo)) + margin_m
    radius, height = primitive.radius or 0.0, primitive.height or 0.0
    if not (math.isfinite(radius) and math.isfinite(height)):
        return False
    if radius > diagonal or height > _HEIGHT_PER_DIAGONAL * diagonal:
        return False
    grow = margin_m + radius
    centre = np.asarray(primitive.centre)
    return bool(
        np.all(np.isfinite(centre)) and np.all((centre >= lo - grow) & (centre <= hi + grow))
    )


def _viewpoint(viewpoint: FloatArray) -> FloatArray:
    """The viewpoint as a finite 3-vector; raises ValueError otherwise."""
    v = np.asarray(viewpoint, dtype=np.float64)
    if v.shape != (3,) or not np.all(np.isfinite(v)):
        raise ValueError(f"viewpoint: expected a finite (3,) point, got {viewpoint!r}")
    return v


def _sphere_on_rays(
    sphere: FloatArray,
    rival: ShapeKind,
    params: FloatArray,
    sample: FloatArray,
    eye: FloatArray,
    models: dict[ShapeKind, tuple[Model, float]],
    fp: FitParams,
    within: Callable[[ShapeKind, FloatArray], bool],
    up: SupportPlane | None = None,
    others: dict[ShapeKind, FloatArray] | None = None,
) -> FloatArray | None:
    """The sphere refined along the rays when it costs, along the rays, no more than every
    cylinder or cone refined the same way (plus ``tie_margin``); else None. The rivals are
    ``rival`` (``params``) and ``others`` (the other curved fits, kind to parameters). The
    sphere starts from the fitted one and from the one its outline gives, each rival from its
    fit and, when it stands on ``up`` (within ``upright_tolerance_deg``), from the same with
    the support's normal for an axis; each kind keeps its cheapest, before or after refining.
    Only parameters that pass ``within`` (the model's limits are checked here) are
    candidates."""
    t_sel = fp.selection_threshold_m
    costs: dict[ShapeKind, tuple[float, FloatArray]] = {}
    others = {rival: params, **{k: x for k, x in (others or {}).items() if k is not rival}}
    starts = [
        (ShapeKind.SPHERE, sphere),
        (ShapeKind.SPHERE, sphere_from_outline(sample, eye)),
    ]
    for kind, x in others.items():
        starts.append((kind, x))
        if up is not None and _orient_up(x[3:6], up, fp.upright_tolerance_deg):
            n = np.asarray(up.normal, dtype=np.float64)
            starts.append((kind, np.concatenate((x[:3], n if n @ x[3:6] > 0 else -n, x[6:]))))
    for kind, x in starts:
        model: RayModel = models[kind][0]  # type: ignore[assignment]
        # A start's end discs serve both its refinement and its own cost.
        ends = (
            fit_ends(model, x, sample, eye, threshold=t_sel)
            if isinstance(model, (CylinderModel, ConeModel))
            else None
        )
        refined = refine_on_rays(
            model, x, sample, eye, threshold=t_sel, iterations=fp.ray_iterations, ends=ends
        )
        for y, y_ends in ((x, ends), (refined, None)):
            if model.within_limits(y) and within(kind, y):
                cost = ray_cost(model, y, sample, eye, threshold=t_sel, ends=y_ends)
                if cost < costs.get(kind, (np.inf, y))[0]:
                    costs[kind] = (cost, y)
    if ShapeKind.SPHERE not in costs or rival not in costs:
        return None
    cost, ball = costs[ShapeKind.SPHERE]
    best = min(c for k, (c, _) in costs.items() if k is not ShapeKind.SPHERE)
    return ball if cost <= best + fp.tie_margin else None


def _standing_under_coarse_depth(
    standing: FloatArray,
    free: FloatArray,
    sample: FloatArray,
    support: SupportPlane | None,
    model: Model,
    fp: FitParams,
) -> FloatArray | None:
    """The standing cylinder ``standing``, refined, in place of the cylinder ``free`` when the
    rule "standing under coarse depth" (module docstring) chooses it; else None."""
    if support is None or _orient_up(free[3:6], support, fp.upright_tolerance_deg):
        return None
    coarse = fp.coarse_standing_share * float(standing[6]) <= fp.selection_threshold_m
    if not coarse:  # before refining, which most clusters need not pay for
        return None
    up = refine_if_better(model, standing, sample, fp.cylinder_threshold_m)
    if not _orient_up(up[3:6], support, fp.upright_tolerance_deg):
        return None
    if fp.coarse_standing_share * float(up[6]) > fp.selection_threshold_m:
        return None
    up_cost, free_cost = (
        _cost(model.distances(x[None, :], sample)[0], fp.selection_threshold_m) for x in (up, free)
    )
    return up if up_cost <= free_cost + fp.coarse_standing_margin else None


def _refused_by_outline(
    points: FloatArray,
    eye: FloatArray,
    support: SupportPlane,
    costs: dict[ShapeKind, float],
    fitted: dict[ShapeKind, FloatArray],
    fp: FitParams,
) -> list[ShapeKind]:
    """The sphere and the standing cylinder among ``costs``, when the cluster's outline closes
    to a point where the depths cannot tell the kinds and a cone is in the running (module
    docstring, "A pointed outline under coarse depth"); else nothing. An outline whose top
    leans (``outline_max_lean``) is a part of a thing, one side cut off by a split or an
    occluder, whose shape says nothing of the whole."""
    if ShapeKind.CONE not in costs:
        return []
    kinds: list[ShapeKind] = [
        k
        for k in (ShapeKind.SPHERE, ShapeKind.CYLINDER)
        if k in costs
        and (k is ShapeKind.SPHERE or _orient_up(fitted[k][3:6], support, fp.upright_tolerance_deg))
    ]
    if not kinds:
        return []
    # The outline costs a k-d tree over every point: first the models' radii stand in for its
    # half width (a whole sphere's or standing cylinder's outline is about as wide as the model),
    # with half the share for a margin.
    radius = max(float(fitted[k][3] if k is ShapeKind.SPHERE else fitted[k][6]) for k in kinds)
    if fp.selection_threshold_m < fp.outline_coarse_share / 2 * radius:
        return []
    outline = outline_rows(points, eye, np.asarray(support.normal), min_rows=fp.outline_min_rows)
    if outline is None or not pointed(
        outline,
        threshold_m=fp.selection_threshold_m,
        coarse_share=fp.outline_coarse_share,
        max_fullness=fp.outline_pointed_fullness,
    ):
        return []
    return kinds if top_lean(outline) <= fp.outline_max_lean else []


def fit_cluster(
    points: FloatArray,
    *,
    support: SupportPlane | None = None,
    params: FitParams | None = None,
    rng: np.random.Generator,
    viewpoint: FloatArray | None = None,
) -> ClusterFit | None:
    """Fit sphere, cylinder, cone and plane(s) to one cluster and choose one (rule above).

    Every candidate is held to :func:`bounded` (a fit outside its own points is never
    output): an unbounded sphere, cylinder or cone is not kept, so each model competes with
    its best bounded candidate, and unbounded planes give way to the next model by the rule.
    Returns None if the cluster has too few points (fewer than 10) for any model, or if no
    bounded fit remains.
    Deterministic for a given ``rng`` state (the work along the rays draws nothing from it).

    ``viewpoint``: the sensor's centre in the points' frame, when known; the sphere is then
    chosen or not along the sensor's rays (module docstring, "Spheres along the rays"). Raises
    ValueError if it is not a finite 3-vector.
    """
    fp = params or FitParams()
    eye = None if viewpoint is None else _viewpoint(viewpoint)
    if len(points) < 10:
        return None
    # Normals from the full-resolution neighbours of each sampled point: with the same number
    # of neighbours their patches are smaller than on the sample, so a short band of a
    # cylinder's side below its top keeps normals square to the axis.
    if len(points) > fp.max_fit_points:
        chosen = np.sort(rng.choice(len(points), fp.max_fit_points, replace=False))
        sample = points[chosen]
    else:
        chosen = None
        sample = points
    normals = normals_at(points, sample, min(fp.normal_neighbours, len(points) - 1))
    t_sel = fp.selection_threshold_m
    # The outline's fringe (of the sample), found when the side wall's cylinder is scored.
    on_fringe: list[Mask] = []

    def cost_of(d: FloatArray, side_wall: FloatArray | None = None) -> float:
        """A candidate's cost from the sample's distances to it; the side wall's cylinder
        (``side_wall``, its parameters) leaves out the points of the outline's fringe that lie
        outside it (module docstring, "Rings and outlines")."""
        if not on_fringe or side_wall is None:
            return _cost(d, t_sel)
        return _cost(d[~(on_fringe[0] & (d >= t_sel) & _outside(side_wall, sample))], t_sel)

    # A sphere or cylinder is seen over a good part of its circumference (a third of it already
    # spans 1.7 radii), so its radius is bounded by the cluster's size: wider ones only imitate
    # a flat face with a slight bend.
    extent = float(np.linalg.norm(column_span(sample)))
    max_radius = min(fp.max_radius_m, fp.max_radius_per_extent * extent)
    models: dict[ShapeKind, tuple[Model, float]] = {
        ShapeKind.SPHERE: (SphereModel(fp.min_radius_m, max_radius), fp.sphere_threshold_m),
        ShapeKind.CYLINDER: (
            CylinderModel(fp.min_radius_m, max_radius, with_caps=True),
            fp.cylinder_threshold_m,
        ),
        ShapeKind.CONE: (
            ConeModel(
                math.radians(fp.min_cone_half_angle_deg),
                math.radians(fp.max_cone_half_angle_deg),
                sample_size=fp.cone_sample_points,
            ),
            fp.cone_threshold_m,
        ),
    }
    costs: dict[ShapeKind, float] = {}
    counts: dict[ShapeKind, int] = {}
    fitted: dict[ShapeKind, FloatArray] = {}
    standing_cylinder: FloatArray | None = None  # the standing search's best, kept or not
    built: dict[ShapeKind, Primitive] = {}  # each kept curved candidate, as scored
    surface: dict[ShapeKind, FloatArray] = {}

    margin = t_sel + fp.snap_distance_m
    box = (column_min(points), column_max(points))

    def curved(kind: ShapeKind, params: FloatArray) -> Primitive:
        if kind is ShapeKind.SPHERE:
            return Primitive(ShapeKind.SPHERE, centre=vec3(params[:3]), radius=float(params[3]))
        if kind is ShapeKind.CYLINDER:
            return _build_cylinder(params, points, support, fp)
        return _build_cone(params, points, support, fp)

    def ranked(kind: ShapeKind, params: FloatArray, cost: float) -> float:
        """A curved candidate's cost with the oblique penalty, as :func:`_choose` ranks it."""
        if support is None or _can_rest(kind, params, support, fp):
            return cost
        return cost + fp.oblique_penalty

    def score(
        kind: ShapeKind, params: FloatArray, d: FloatArray | None = None, side_wall: bool = False
    ) -> None:
        """Keep a candidate (in place of the model's last one) if it is bounded; ``d``: the
        sample's distances to it, when known; ``side_wall``: the side wall's cylinder."""
        if kind is ShapeKind.CONE and _stands_on_its_tip(params, support, fp):
            return  # a thing widening upwards: not a cone ("Standing and widening upwards")
        primitive = curved(kind, params)
        if not bounded(primitive, points, margin_m=margin, box=box):
            return  # a fit that leaves its own points is never a candidate
        if d is None:
            d = models[kind][0].distances(params[None, :], sample)[0]
        cost = cost_of(d, params if side_wall else None)
        fitted[kind], surface[kind], costs[kind] = params, d, cost
        built[kind] = primitive

    for kind, (model, thr) in models.items():
        res = ransac(
            model,
            sample,
            normals,
            threshold=thr,
            rng=rng,
            max_iterations=fp.max_iterations,
            refine=False,
            min_iterations=0 if kind is ShapeKind.SPHERE else fp.min_iterations,
            preview_points=fp.preview_points,
        )
        if res is not None:
            if kind is ShapeKind.CYLINDER:  # PITT's cylinder has no end discs
                pitt_d = CylinderModel(with_caps=False).distances(res.params[None, :], sample)[0]
                counts[kind] = int((pitt_d < thr).sum())
            else:
                counts[kind] = int(res.inliers.sum())
            score(kind, res.params, res.distances)
    if support is not None:
        # Standing cones and cylinders: hypotheses with the support's normal (gravity, the
        # commonest axis of a thing on a table) for an axis need two points, and noisy normals
        # spoil them far less than free ones (seen from far, free cylinder hypotheses may find
        # only a lying cylinder). The cylinders' draws come from a generator of their own
        # (spawning one leaves ``rng`` as it was), so adding them moved no other search's draws.
        standing = (
            (ShapeKind.CONE, UprightConeModel, fp.upright_cone_iterations),
            (ShapeKind.CYLINDER, UprightCylinderModel, fp.upright_cylinder_iterations),
        )
        for kind, upright, iterations in standing:
            if iterations <= 0:
                continue
            model, threshold = models[kind]
            res = ransac(
                upright(model, support.normal),  # type: ignore[arg-type]
                sample,
                normals,
                threshold=threshold,
                rng=rng if kind is ShapeKind.CONE else rng.spawn(1)[0],
                max_iterations=iterations,
                refine=False,
                min_iterations=iterations // 2,
                preview_points=fp.preview_points,
            )
            if res is None:
                continue
            if kind is ShapeKind.CYLINDER:
                standing_cylinder = res.params
            if cost_of(res.distances) < costs.get(kind, np.inf):
                score(kind, res.params, res.distances)
    # Planes, one after another on what the previous ones left.
    plane_model = PlaneModel()
    remaining = np.ones(len(sample), dtype=bool)
    plane_d = np.full(len(sample), np.inf)
    planes: list[tuple[FloatArray, FloatArray]] = []
    for _ in range(fp.max_planes):
        if remaining.sum() < max(10, fp.min_plane_share * len(sample)):
            break
        res = ransac(
            plane_model,
            sample[remaining],
            normals[remaining],
            threshold=fp.plane_threshold_m,
            rng=rng,
            max_iterations=fp.max_plane_iterations,
        )
        if res is None or res.inliers.sum() < max(10, fp.min_plane_share * len(sample)):
            break
        if not planes:
            counts[ShapeKind.PLANE] = int(res.inliers.sum())
        d = plane_model.distances(res.params[None, :], sample)[0]
        plane_d = np.minimum(plane_d, d)
        planes.append((res.params, sample[remaining][res.inliers]))
        remaining &= d >= fp.plane_threshold_m
    if len(planes) > 1:
        # Points along a box edge lie within the threshold of both faces: give each point to
        # its nearest face and refit every face on its own points, so edges do not tilt them.
        stacked = np.array([p for p, _ in planes])
        d_all = plane_model.distances(stacked, sample)
        nearest = d_all.argmin(axis=0)
        refitted = []
        for i, (p, inl) in enumerate(planes):
            own = sample[(nearest == i) & (d_all[i] < fp.plane_threshold_m)]
            if len(own) >= 3:
                centre = own.mean(axis=0)
                n = np.linalg.svd(own - centre, full_matrices=False)[2][2]
                n = n if n @ p[:3] >= 0 else -n
                p, inl = np.concatenate((n, [-n @ centre])), own
            refitted.append((p, inl))
        planes = refitted
        plane_d = plane_model.distances(np.array([p for p, _ in planes]), sample).min(axis=0)
    if planes:
        surface[ShapeKind.PLANE], costs[ShapeKind.PLANE] = plane_d, cost_of(plane_d)
    plane_cost = costs.get(ShapeKind.PLANE, np.inf)
    charges = (
        parameter_charges(
            len(planes), len(sample), charge=fp.parameter_charge, noise_factor=fp.noise_factor
        )
        if fp.parameter_charge > 0 and planes
        else None
    )
    if planes and costs.get(ShapeKind.CONE, np.inf) > plane_cost - fp.tie_margin:
        # A cone on its side shows its flat base: hypotheses drawn from the whole cluster then
        # mostly hold a base point and miss the cone. When the planes beat the cone, draw more
        # from what the first plane leaves (the lateral surface) and keep the cone if it
        # explains the whole cluster better.
        off = plane_model.distances(planes[0][0][None, :], sample)[0] >= fp.plane_threshold_m
        if off.sum() >= max(20, fp.min_plane_share * len(sample)):
            model, thr = models[ShapeKind.CONE]
            res = ransac(
                model,
                sample[off],
                normals[off],
                threshold=thr,
                rng=rng,
                max_iterations=fp.max_iterations,
                refine=False,
                min_iterations=fp.min_iterations,
                preview_points=fp.preview_points,
            )
            if res is not None:
                d = model.distances(res.params[None, :], sample)[0]
                if cost_of(d) < costs.get(ShapeKind.CONE, np.inf):
                    score(ShapeKind.CONE, res.params, d)
    for plane, inliers in planes[:2]:
        # A cone showing its base: the base plane gives the axis, the rim of the disc its
        # centre and radius, the lateral points the height (one direct hypothesis). A base
        # seen at all holds a good share of the points.
        if len(inliers) < fp.min_base_share * len(sample):
            continue
        model = models[ShapeKind.CONE][0]
        guess = _cone_on_base(plane, sample, fp.plane_threshold_m)
        if guess is not None and model.within_limits(guess):
            d = model.distances(guess[None, :], sample)[0]
            if cost_of(d) < costs.get(ShapeKind.CONE, np.inf):
                score(ShapeKind.CONE, guess, d)
    if not costs:
        return None
    # Least-squares refinement only for the curved candidates still in the running.
    best = min(costs.values())
    for kind in list(fitted):
        if costs[kind] <= best + fp.refine_margin:
            model, thr = models[kind]
            score(kind, refine_if_better(model, fitted[kind], sample, thr))
    if support is not None and fp.side_wall_cut_m > 0:
        # After the refinements: the side wall's circle is a least-squares fit already, and
        # refined on every point the fringe it is scored without would pull it wider again.
        side = _side_wall_cylinder(sample, support, fp, models[ShapeKind.CYLINDER][0])
        # Within the tie margin the cylinder fitted on every point stays; and a cylinder the
        # planes would beat anyway changes nothing.
        to_beat = min(
            costs.get(ShapeKind.CYLINDER, np.inf) - fp.tie_margin,
            costs.get(ShapeKind.PLANE, np.inf) + fp.tie_margin,
        )
        if side is not None and eye is not None and fp.fringe_cells > 0:
            # The fringe only when leaving out every far point outside could be enough.
            d, out = side[1], _outside(side[0], sample)
            if _cost(d[~((d >= t_sel) & out)], t_sel) < to_beat:
                rim = fringe(points, eye, cells=fp.fringe_cells, cell_steps=fp.fringe_cell_steps)
                on_fringe.append(rim if chosen is None else rim[chosen])
        if side is not None and cost_of(side[1], side[0]) < to_beat:
            score(ShapeKind.CYLINDER, *side, side_wall=True)
    cylinder_cost = costs.get(ShapeKind.CYLINDER, np.inf)
    if (
        cylinder_cost <= best + fp.refine_margin
        and cylinder_cost < costs.get(ShapeKind.CONE, np.inf)
        and not _orient_up(fitted[ShapeKind.CYLINDER][3:6], support, fp.upright_tolerance_deg)
        and fp.coarse_standing_share * float(fitted[ShapeKind.CYLINDER][6]) > t_sel
    ):
        # Cones around a cylinder that beats every cone, does not stand (standing cones have
        # hypotheses of their own) and is not seen under coarse depth (the distances to the
        # surface then tell a cone from a cylinder no better than the fit's draws do): a narrow
        # leaning cone's free hypotheses often miss it, and a cylinder then fits it best.
        cone_model = models[ShapeKind.CONE][0]
        assert isinstance(cone_model, ConeModel)  # as built above
        for x in _cones_around(
            fitted[ShapeKind.CYLINDER],
            sample,
            surface[ShapeKind.CYLINDER] < t_sel,
            cone_model,
            max_points=fp.cone_around_points,
            iterations=fp.cone_around_iterations,
        ):
            if not cone_model.within_limits(x):
                continue
            d = cone_model.distances(x[None, :], sample)[0]
            # Ranked as the rule ranks the curved models: with the oblique penalty, so that a
            # resting cone is not given up for a slightly cheaper tilted one.
            if ShapeKind.CONE not in costs or ranked(ShapeKind.CONE, x, cost_of(d)) < ranked(
                ShapeKind.CONE, fitted[ShapeKind.CONE], costs[ShapeKind.CONE]
            ):
                score(ShapeKind.CONE, x, d)
    if standing_cylinder is not None and ShapeKind.CYLINDER in costs:
        up = _standing_under_coarse_depth(
            standing_cylinder,
            fitted[ShapeKind.CYLINDER],
            sample,
            support,
            models[ShapeKind.CYLINDER][0],
            fp,
        )
        if up is not None:
            free_cost = costs[ShapeKind.CYLINDER]
            score(ShapeKind.CYLINDER, up)
            if fitted[ShapeKind.CYLINDER] is up:  # bounded: it meets the others at the lower cost
                costs[ShapeKind.CYLINDER] = min(free_cost, costs[ShapeKind.CYLINDER])
    if (
        support is not None
        and ShapeKind.PLANE in costs
        and _choose(costs, fitted, support, fp, points, charges=charges) is ShapeKind.PLANE
    ):
        # A round thing that widens upwards has no model of its own (standing cones point
        # up): the planes bend round it and win unless the cylinder is scored without taper.
        cylinder = models[ShapeKind.CYLINDER][0]
        assert isinstance(cylinder, CylinderModel)
        untapered = _without_taper(sample, support, fp, cylinder)
        if untapered is not None and cost_of(untapered[1]) < costs.get(ShapeKind.CYLINDER, np.inf):
            score(ShapeKind.CYLINDER, *untapered)
    sphere_on_rays: bool | None = None
    if eye is not None and ShapeKind.SPHERE in costs:
        # The sphere against the model the rule would choose without it, along the rays.
        rival = (
            _choose(
                {k: c for k, c in costs.items() if k is not ShapeKind.SPHERE},
                fitted,
                support,
                fp,
                points,
                charges=charges,
            )
            if len(costs) > 1
            else None
        )
        if rival in (ShapeKind.CYLINDER, ShapeKind.CONE):
            sphere_on_rays = False
            if costs[ShapeKind.SPHERE] - costs[rival] <= fp.ray_gate:
                ball = _sphere_on_rays(
                    fitted[ShapeKind.SPHERE],
                    rival,
                    fitted[rival],
                    sample,
                    eye,
                    models,
                    fp,
                    lambda k, x: bounded(curved(k, x), points, margin_m=margin, box=box),
                    support,
                    {k: fitted[k] for k in (ShapeKind.CYLINDER, ShapeKind.CONE) if k in fitted},
                )
                if ball is not None:
                    score(ShapeKind.SPHERE, ball)
                    sphere_on_rays = True
    # The taper is measured on every point: on the sample its noise alone passed the rule.
    kind = _choose(costs, fitted, support, fp, points, sphere_on_rays, charges)
    if eye is not None and support is not None and kind in (ShapeKind.SPHERE, ShapeKind.CYLINDER):
        # Under coarse depth the outline, which range noise leaves sharp, may contradict the
        # choice: a pointed outline is neither a sphere's nor a standing cylinder's.
        refused = _refused_by_outline(points, eye, support, costs, fitted, fp)
        for k in refused:
            del costs[k]
        if refused:
            kind = _choose(costs, fitted, support, fp, points, sphere_on_rays, charges)
    while True:
        if kind is ShapeKind.PLANE:
            plane, inl = max(planes, key=lambda p: len(p[1]))
            prim = _build_plane(plane, sample, inl)
        else:
            prim = built[kind]
        if bounded(prim, points, margin_m=margin, box=box) and not (
            kind is ShapeKind.CYLINDER and _sunk_in_support(prim, support, fp)
        ):
            break
        # A fit that leaves its own points is never output, nor the bend of a face taken for
        # a cylinder lying in the table ("A lying cylinder rests on something").
        del costs[kind]
        if not costs:
            return None
        kind = _choose(costs, fitted, support, fp, points, sphere_on_rays, charges)
    ratio = float((surface[kind] < t_sel).mean())
    prim = Primitive(**{**prim.__dict__, "inlier_ratio": ratio})
    return ClusterFit(prim, costs, counts)
