"""The parameters of segmentation, one frozen value; lengths in metres."""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class SegmentationParams:
    """Parameters of :func:`segment`; lengths in metres."""

    voxel_m: float = 0.01
    max_depth_m: float | None = None
    """A fixed depth cut; None: the cut follows the sensor's noise (``max_range_noise_m``)."""
    max_range_noise_m: float = 0.02
    default_depth_m: float = 3.0
    """The cut when the noise is not known (an unorganised cloud, or a noiseless image)."""
    target_points: int = 60_000
    filter_artefacts: bool = True
    support_threshold_m: float = 0.01
    support_iterations: int = 500
    max_support_tilt_deg: float = 10.0
    min_support_fraction: float = 0.03
    max_planes: int = 5
    min_plane_extent_m: float = 0.25
    above_margin_m: float = 0.008
    max_height_m: float = 0.6
    max_tall_height_m: float = 1.2
    """How high a cluster that stands on its support and is cut at ``max_height_m`` may grow
    (:func:`grown_upwards`): what ends under it is a tall object, what reaches it a part of
    something larger."""
    edge_margin_m: float = 0.02
    outlier_neighbours: int = 10
    outlier_std_ratio: float = 3.0
    cluster_eps_m: float = 0.03
    cluster_min_points: int = 3
    min_cluster_voxels: int = 12
    split_touching: bool = True
    min_split_extent_m: float = 0.07
    max_ring_gap_deg: float = 125.0
    """The widest angle between neighbouring parts of a cut, seen from their common centre
    across the support, for the parts to close a ring (:mod:`shapes.ring_cut`) and the cut to be
    refused: a bowl's inside. Over the tuned-on scans' taken cuts of three parts or more (seeds
    0-2), the rings' widest gaps are 89-112 degrees, the other cuts' 142-179."""
    max_lying_height_m: float = 0.075
    """The height over the support under which every part of a seam cut must stay for the cut to
    be refused as one thing lying on the support (:mod:`shapes.lying_cut`: a drill on its side).
    Over the taken cuts of the 24 tuned-on scans (seeds 0-2) and the simulated bench's, the
    tallest part (98th percentile of its voxels' heights) is 5.1-5.6 cm on the lying drill and
    9.8 cm or more on every cut between objects measured side by side."""
    min_part_colour_difference: float = 40.0
    """How far apart (CIELAB delta E) the median colours of every two touching parts of a cut
    refused as stacked must lie for the cut to be taken with the stacked parts joined
    (:mod:`shapes.colour_seam`: a drill lying against a clamp and a sugar box; 0: never). Over
    the 24 tuned-on scans (seeds 0-2), every other cut refused as stacked has a touching pair
    27.2 or closer; the lying drill, clamp and sugar box's closest pair is 55.6-56.1."""
    occlusion_slope: float = 1.5
    """How steeply (depth step over distance across the ray) neighbouring pixels of one
    surface may differ in depth; a steeper step is an occlusion edge or a face seen edge-on,
    across which a surface in front is parted from what it hides
    (:mod:`shapes.segment.occlusion`; 0: never)."""
    occlusion_noise_multiple: float = 10.0
    """How many times the depth noise at its range a step must also exceed to part surfaces:
    a step of a few noise levels (a Kinect's depth quantisation) is one surface's."""
    min_support_rise_m: float = 0.25
    max_base_height_m: float = 0.04
    floor_step_m: float = 0.03
    support_cell_m: float = 0.05
    """The grid on which a plane's voxels are joined into pieces (a support's main piece, a
    tilted plane's pieces: :mod:`shapes.plane_pieces`)."""
    max_band_tilt_deg: float = 3.0
    """How far (degrees) a horizontal plane may tilt from a larger one and still be part of its
    band (:mod:`shapes.segment.bands`): 0.1-2.5 deg for the parallel planes in a support's band
    on the tuned-on scans, 6.4-6.7 deg for the scattered planes across the fr2 desk."""
    min_shared_ground: float = 0.5
    """The share of a horizontal plane's voxels that must lie in cells (``support_cell_m``)
    where a larger parallel plane has voxels for it to be part of that plane's band
    (:mod:`shapes.segment.bands`): 0.55-0.77 for the living room's floor planes."""
    min_main_piece_share: float = 0.5
    """The share of a horizontal plane's voxels its main piece must hold for the plane to be a
    surface of its own; a plane scattered in smaller pieces is reduced to its main piece
    (:func:`shapes.plane_pieces.is_scattered`)."""
    faces_by_main_piece: bool = True
    """Whether a plane is judged a face of objects (or a part of what stands on a support) by
    its main piece (:func:`shapes.plane_pieces.main_piece`, on the ``support_cell_m`` grid)
    rather than by all its inliers, unless it is scattered (``min_main_piece_share``) or rises
    past ``max_height_m`` elsewhere (:func:`shapes.segment.supports._judged_voxels`;
    docs/perception.md, "Would-be faces judged by their main piece (stop 39, late)")."""
    extent_margin_m: float = 0.05
    """How far past the hull of its support's main piece an object's centre may lie."""
    cut_band_m: float = 0.03
    """How near the scene's limits (``max_height_m`` over the support, the depth cut) a voxel
    or point counts as reaching them (the depth cut's band grows to 3 sigma of the noise)."""
    min_cut_share: float = 0.01
    """The share of a cluster's voxels (or points) reaching a limit that makes it cut by it,
    and so a part of something larger than the scene, not an object."""
    min_cut_voxels: int = 3
    """As ``min_cut_share``, a count: one stray voxel at the limit cuts nothing."""
    border_band_px: int = 8
    """How near an edge of the image's valid window (other than the edge the camera looks
    down through) a point counts as cut by it (:mod:`shapes.view`): four sampled pixels at a
    640 x 480 frame's stride of 2; the window's edge itself wanders by a few pixels where
    flying pixels were dropped."""
    floating_probe_px: int = 8
    """How far past a cluster's lower outline in the image something nearer is looked for,
    which hides its bottom (:func:`floats`)."""
    min_hidden_share: float = 0.5
    """The share of a cluster's lower outline that something nearer must hide for a bottom
    seen above ``max_base_height_m`` to be hidden rather than hanging (:func:`floats`)."""
    support_edge_depth_m: float = 0.08
    """How far under a support's plane its edge reaches (the top's thickness, its front face,
    an apron): what hides the top of a cluster on a lower support from that high up is the
    support's edge, and the cluster stands under it (:mod:`shapes.support_edge`)."""
    min_edge_hidden_share: float = 0.5
    """The share of a cluster's upper outline that a higher support's edge must hide for the
    cluster to stand under that edge (:mod:`shapes.support_edge`); the same half as
    ``min_hidden_share`` asks of a lower outline."""
    max_edge_share: float = 0.5
    """The share of a cluster's pixels at a depth edge above which it is a band of an edge's
    mixed pixels and gives no primitive (:mod:`shapes.segment.slivers`; 1: never). Over the
    primitives the bench matches to a measured object on the 24 tuned-on scans (seeds 0-2),
    the share is 0.16 at most (the fr1 desk's purple device); the one stray above half, 0.83,
    is the line of mixed pixels along the living room's laptop screen (docs/perception.md,
    "Clusters made of a depth edge's pixels (stop 40)")."""
    sliver_window_px: int = 5
    """The side (full-resolution pixels) of the window in which a depth edge is looked for
    around a cluster's pixel (:func:`shapes.segment.slivers.edge_share`)."""
    sliver_jump_ratio: float = 0.05
    """How much farther than a cluster's pixel, as a share of its depth, a pixel of that window
    must lie to be past a depth edge: steeper than a surface seen at 80 degrees from its
    normal."""
    sliver_min_farther: int = 5
    """How many pixels of that window must lie farther than the pixel by the jump for it to be
    at a depth edge: one side of the window (a row or column of it beyond a straight edge),
    which a few scattered outliers do not make."""
    measure_support: bool = True
    """Whether each support that carries clusters (the largest plane, when none does) is
    measured again over its main piece, weighed by the depth noise and robustly
    (:mod:`shapes.segment.support_fit`), for the plane reported as the support
    (:attr:`Segmentation.support`, the pipeline's support primitives); the clusters are cut,
    and their objects fitted, with the plane search's plane."""
    sliver_samples: int = 200
    """How many of a cluster's pixels (evenly spread) :func:`edge_share` judges."""
    fragment_max_voxels: int = 40
    """A cluster with fewer voxels than this (1 cm voxels: its visible surface in cm²) is a
    fragment, joined to the object it touches (:mod:`shapes.segment.fragments`; 0: never). Over
    the tuned-on scans (seeds 0-2) the pieces of found objects within 5 cm of them have 12-30
    voxels; the one measured object under 70 voxels that touches a neighbour in the image within
    6 cm (the fr1 tray's black device) has 41."""
    fragment_gap_m: float = 0.05
    """How far in 3D a fragment may lie from the cluster it joins: the pieces lie 2.4-4.4 cm from
    their objects, the black device 6.0 cm from its neighbour."""
    fragment_touch_px: int = 4
    """How near in the image (rows and columns) a fragment's pixels must come to the cluster's
    it joins: two strides of a 640 x 480 frame, nothing of the support seen between them. The
    pieces come within 2-4 pixels of their objects; measured small objects beside a neighbour
    6-12 (the mice, the beige cup, the blue packet, the purple device)."""
