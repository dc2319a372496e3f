"""Perception for Engram: point clouds in, tracked and averaged geometric primitives out.

"shapes" here means **geometric primitives** (spheres, cylinders, cones, planes) fitted to
point clouds, not SHACL shapes. The package uses numpy and open3d only; it imports nothing of
Engram's and no RDF code, so the memory client (``api``) depends on it, never the reverse.

Stages, each usable on its own:

- inputs: :class:`Frame` (validated arrays, organised or not), :func:`frame_from_depth_image`,
  :func:`open_source` (PLY/PCD checked against their headers by :mod:`shapes.cloudfile`,
  NumPy files, ROS 1 / ROS 2 bags), the synthetic tabletop generator :mod:`shapes.synthetic`
  with ground truth, and :mod:`shapes.sensor`, a simulated 640 x 480 depth camera with the
  artefacts of real sensors;
- :mod:`shapes.artefacts`: depth noise measured per frame, flying pixels, veils, sparse points;
- :mod:`shapes.gravity`: up from the scene's dominant support when the sensor's pose is not
  known (``PerceptionParams(gravity_from_scene=True)``);
- :mod:`shapes.segment` (a package; its function is :func:`shapes.segment.segment`): depth cut,
  voxel grid, planes, the support rule (the horizontal plane with objects on it; a plane standing
  on it is part of an object), points above it, clusters, touching objects split
  (:mod:`shapes.split`);
- :func:`fit_cluster`: sphere / cylinder / cone / plane RANSAC and the shape choice, every
  primitive within its own points;
- :class:`Tracker`: stable ids; :mod:`shapes.colour`: colour per object;
- :class:`SceneAverager`: per-id averages per shape, majority shape, scene changes; a scene
  holds its objects and the supports they stand on (Planes);
- :class:`Perception`: all of it for a stream of frames, yielding :class:`StableScene` events
  (and, at the end of a finite source, the scene it has; :meth:`Perception.why_no_scene`).

>>> import numpy as np
>>> from shapes.synthetic import random_scene
>>> rng = np.random.default_rng(0)
>>> scene = random_scene(rng, n_objects=2)
>>> perception = Perception(seed=0)
>>> scenes = list(perception.stable_scenes(scene.render(rng).frame for _ in range(8)))
>>> len(scenes), len(scenes[0].primitives)
(1, 2)
"""

from shapes.average import Observation, SceneAverager, SceneChange, SceneEvent, StableScene
from shapes.bags import read_bag, write_bag
from shapes.colour import colour_name, mean_colour
from shapes.errors import InvalidCloudError, ShapesError, SourceError
from shapes.fit import ClusterFit, FitParams, fit_cluster, pitt_choice
from shapes.frame import Frame, frame_from_depth_image
from shapes.io import open_source, read_cloud_file, source_length
from shapes.pipeline import FrameResult, Perception, PerceptionParams
from shapes.segment import Cluster, Segmentation, SegmentationParams
from shapes.track import Tracker
from shapes.types import Primitive, ShapeKind, SupportPlane

__all__ = [
    "Cluster",
    "ClusterFit",
    "FitParams",
    "Frame",
    "FrameResult",
    "InvalidCloudError",
    "Observation",
    "Perception",
    "PerceptionParams",
    "Primitive",
    "SceneAverager",
    "SceneChange",
    "SceneEvent",
    "Segmentation",
    "SegmentationParams",
    "ShapeKind",
    "ShapesError",
    "SourceError",
    "StableScene",
    "SupportPlane",
    "Tracker",
    "colour_name",
    "fit_cluster",
    "frame_from_depth_image",
    "mean_colour",
    "open_source",
    "pitt_choice",
    "read_bag",
    "read_cloud_file",
    "source_length",
    "write_bag",
]
