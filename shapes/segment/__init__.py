"""Segmentation: from a raw frame to the object clusters standing on their supports.

Steps (PITT's, with its quirks fixed; see ``shared/reference/pitt-perception.md`` §4):

1. depth cut in the sensor frame, where the sensor's depth noise reaches ``max_range_noise_m``
   (:func:`~shapes.segment.survey.depth_cut_m`; a Kinect keeps a floor 4.4 m away, not its walls
   at 5 m). On an organised frame the depth noise is measured from the image and flying pixels
   and veils are dropped (:mod:`shapes.artefacts`), judged on the full-resolution image; only
   every k-th pixel of every k-th row is kept, k chosen from the points within range to leave
   about ``target_points`` points (:func:`~shapes.segment.survey.pixel_stride`; a 640 x 480
   frame keeps one pixel in four, still about 4 to 13 per 1 cm voxel of a surface facing the
   camera at 1.5 to 0.8 m, and a cluster its hundreds of points), and the points go to the world
   frame (z up, the gravity direction);
2. voxel grid (``voxel_m``), laid in the *sensor* frame, so that the pose moves the voxels but
   never changes which points share one (the output does not depend on the pose's last digits):
   each occupied voxel becomes the mean of its points, computed in numpy so that every
   full-resolution point keeps the index of its voxel. Voxels with fewer than two occupied
   neighbours (stray returns, outliers) are set aside;
3. planes: RANSAC (numpy, seeded) finds up to ``max_planes`` planes one after another, each
   holding at least ``min_support_fraction`` of the voxels and spanning at least
   ``min_plane_extent_m`` (a smaller one is the face of an object, and the search stops).
   Threshold 1 cm, not PITT's 2 cm, which ate the bottom of every object. A horizontal plane
   in the band of a larger one (parallel, beside it with no gap, among its voxels, solid) is
   folded into it first: an undulating floor's band is one support, whose noise margin is its
   largest plane's (:mod:`shapes.segment.bands`). A plane whose voxels
   all lie above a horizontal one, less than ``max_height_m`` over it, in pieces none of which
   spans ``min_plane_extent_m``, is the fronts of objects standing in a row or the tops of
   objects of one height (seen on clean scans), not a wall or a shelf: its voxels stay free
   (:func:`shapes.segment.supports._faces_on`). Likewise a plane standing on a larger horizontal
   one, inside it and lower than ``min_support_rise_m`` (horizontal) or ``max_height_m``
   (tilted) over it, is part of an object (a box's top, a laptop's open lid) and its voxels stay
   free, except a horizontal one less than ``floor_step_m`` over it (a rug, a seam of the
   floor), which joins the support (:func:`shapes.segment.supports._standing_on`). A plane is
   also judged by its connected pieces (:mod:`shapes.plane_pieces`): a tilted plane whose main
   piece stands on a larger horizontal one is an object's face, and its standing pieces stay
   free however far the plane's other voxels reach; a would-be support whose main piece holds
   under ``min_main_piece_share`` of its voxels is no support, and removes only its main piece's
   voxels (:func:`shapes.segment.supports._supports_by_pieces`);
4. **the support rule**: a support is a *horizontal* plane (normal within
   ``max_support_tilt_deg`` of world z, i.e. of gravity) *with objects on it*. Every voxel that
   belongs to no plane and lies between ``above_margin`` and ``max_height_m`` above a horizontal
   plane, inside the xy bounding box of the plane's *main piece* (its largest connected part,
   :mod:`shapes.support_region`) shrunk by ``edge_margin_m``, goes to the *nearest such plane
   below it*: objects on a table belong to the table, not to the floor under it. A cluster (step
   6) whose centre lies outside the main piece's convex hull grown by ``extent_margin_m`` does
   not stand on the support (the back of a chair rising over a desk's front edge) and is
   dropped. A cluster cut by the scene's limits (``min_cut_share`` of its voxels within
   ``cut_band_m`` of ``max_height_m`` over its support, or of its points near the depth cut) is
   a part of something larger (a wall, a chair's back) and is dropped too
   (:func:`shapes.segment.objects.cut_by_limits`), unless it stands on the support and, grown
   upwards through the free voxels over the band, ends under ``max_tall_height_m`` in view (a
   rack case: :func:`shapes.segment.tall.grown_upwards`), as is one cut by an edge of the
   image's valid window other than the one the camera looks down through (:mod:`shapes.view`),
   one whose bottom is seen hanging over the support (a chair's seat;
   :func:`shapes.segment.objects.floats`), and one standing under any such part (a chair's base;
   :func:`shapes.segment.objects.not_under`), and one on a lower support that reaches under a
   higher support's outline and whose top that support's edge hides (a desk's leg seen on the
   floor under its front edge; :mod:`shapes.support_edge`). A would-be support that crosses a
   larger horizontal plane, lying partly under it and partly over it, is no support and its
   voxels stay free (:func:`shapes.segment.supports._crosses`). Every horizontal plane that gets
   clusters is reported (:attr:`Segmentation.supports`); the one with the most object voxels is
   *the* support. The largest plane (often the floor or a wall) wins nothing by its size.
   The plane reported is each support measured again over its main piece, weighed by the
   depth noise (:mod:`shapes.segment.support_fit`); the clusters keep the plane search's;
5. the above-table margin adapts to the noise: ``above_margin = max(above_margin_m, 3 sigma)``
   with sigma the robust spread of the support's voxels about the plane; full-resolution points
   are cut at ``max(above_margin_m, 2 sigma(z))`` with ``sigma(z) = sigma_1m z²`` (measured on
   the image, or from the support's residuals on an unorganised cloud; a cloud that is not in a
   camera frame, with points at z <= 0.1 m, gets one sigma for every range);
6. statistical outlier removal and DBSCAN (open3d) on those voxels; each cluster is cut along
   its concave seams, which separates objects that touch (:mod:`shapes.split`) when every part
   reaches down to the support (a handle or a shoulder hangs above it), unless the parts close a
   ring around a common centre (a bowl's inside, :mod:`shapes.ring_cut`), and parted at
   occlusion edges where a thing lies across another in front of it, or a hand hangs in from the
   image's edge (:mod:`shapes.segment.occlusion`); clusters with fewer than
   ``min_cluster_voxels`` voxels are dropped;
7. each cluster gets its full-resolution points (and colours) back through the voxel index;
   a cluster most of whose pixels lie at a depth edge (a line of mixed pixels along a
   silhouette) is dropped (:mod:`shapes.segment.slivers`), and a cluster under
   ``fragment_max_voxels`` voxels that touches a larger one in the image and lies within
   ``fragment_gap_m`` of it in 3D (a cup's rim, a strip of a laptop) joins it
   (:mod:`shapes.segment.fragments`).

When there is no cluster, :attr:`Segmentation.reason` says why in one line: no support found
(with the planes seen), or no clusters above it, or clusters too small.

The modules, in the order of the steps (imports go one way, each only from those above it):

- :mod:`shapes.segment.params`: :class:`SegmentationParams`;
- :mod:`shapes.segment.planes`: step 3's search, RANSAC, one plane after another;
- :mod:`shapes.segment.survey`: steps 1 to 3 in the sensor frame, :func:`survey`;
- :mod:`shapes.segment.bands`: a support seen as a band of parallel planes is one plane;
- :mod:`shapes.segment.supports`: which planes are supports and which are faces of objects;
- :mod:`shapes.segment.free_voxels`: the voxels free of the planes, and the support each
  stands over;
- :mod:`shapes.segment.splitting`: which of the splitter's cuts are taken;
- :mod:`shapes.segment.occlusion`: clusters parted at occlusion edges;
- :mod:`shapes.segment.clusters`: :class:`Cluster`, the clusters over one support;
- :mod:`shapes.segment.reach`: how far the scene reaches (the depth cut, the image's window);
- :mod:`shapes.segment.objects`: the rules of what is an object of the scene, in their order;
- :mod:`shapes.segment.tall`: clusters cut at the band's top, grown upwards;
- :mod:`shapes.segment.slivers`: clusters made of a depth edge's pixels give no primitive;
- :mod:`shapes.segment.fragments`: a fragment of an object joins the object it touches;
- :mod:`shapes.segment.support_fit`: each support measured again over its main piece, weighed
  by the depth noise: the plane reported;
- :mod:`shapes.segment.segmentation`: :func:`segment`, the steps in order, and
  :class:`Segmentation`.
"""

from shapes.segment.clusters import Cluster
from shapes.segment.params import SegmentationParams
from shapes.segment.planes import ransac_plane
from shapes.segment.segmentation import Segmentation, segment
from shapes.segment.survey import Survey, depth_cut_m, pixel_stride, survey, voxel_grid

__all__ = [
    "Cluster",
    "Segmentation",
    "SegmentationParams",
    "Survey",
    "depth_cut_m",
    "pixel_stride",
    "ransac_plane",
    "segment",
    "survey",
    "voxel_grid",
]
