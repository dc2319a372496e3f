"""What the round things of the tuned-on desks cost as each model, and as their own shape.

For each round thing of ``desk_tum``, ``desk_fr2_tum_0`` and ``desk_fr2_tum_1`` that
``bench/perception.py`` gives as one primitive of the wrong kind, or too far off (and, for
comparison, the round things beside them that come out right), one line with:

- ``range``, ``step``: the median range of the cluster's points and the median gap between
  their distinct depths (the sensor's depth step there); ``T``: the selection threshold;
- ``cluster``: its points, the share of them inside the object's pixel boxes
  (``tests/data/real_scans/measure.py``); and of the object's own points
  (``measure.object_mask``: its boxes, height band, depth cut and wall cut, as the ground truth
  is measured), among the points segmentation keeps, the shares in this cluster, in other
  clusters, in a plane of the survey (a wall or the desk) and in none;
- ``costs``: every model's cost as ``shapes.fit.fit_cluster`` gives it (the pipeline's
  arguments and generator), and the kind and radius chosen;
- ``standing floor``: the cheapest standing cylinder (its axis the support's normal) over a grid
  of feet (4 mm steps, 10 cm round the centroid) and radii (1.5-8 cm, 2.5 mm steps), scored the
  same way on the points the fit scores its candidates on (its sample of at most
  ``max_fit_points``); ``measured``: the ground truth's own cylinder, where it has a
  radius. When both cost more than the planes, no rule on these costs
  makes the thing round;
- ``relief``: across the object's middle rows, how much nearer its nearest pixel is than the
  third pixel in from each edge, against what a circle of its measured radius (or of half the
  row's width) would give there: how much of its roundness the depths keep;
- ``centre``: the primitive's centre from the cluster's centroid, along the line of sight and
  across it.

All on the scans tuned on; seed 0 unless ``--seed``. Run from the repository root::

    PYTHONPATH=. .venv/bin/python bench/perception_round_costs.py
"""

import argparse
import json
import os
from pathlib import Path
from typing import Any

for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import numpy as np  # noqa: E402

import shapes.pipeline as pipeline  # noqa: E402
from shapes import Perception, PerceptionParams, open_source  # noqa: E402
from shapes.fit import fit_cluster  # noqa: E402
from shapes.fit.models import CylinderModel  # noqa: E402
from tests.shapes.real_scans import load_script  # noqa: E402

SCANS = Path(__file__).parents[1] / "tests" / "data" / "real_scans"
measure = load_script(SCANS / "measure.py", "measure")

ROUND = {
    "desk_tum": ["beige cup", "jar", "clear bottle", "brown bottle", "green bottle", "mug"],
    "desk_fr2_tum_0": ["back can", "left can", "mug"],
    "desk_fr2_tum_1": ["left can", "back can", "mug"],
}


def _cost(d: np.ndarray, threshold: float) -> np.ndarray:
    return np.asarray((np.minimum(d / threshold, 1.0) ** 2).mean(axis=-1))


def standing_floor(
    points: np.ndarray, normal: np.ndarray, offset: float, threshold: float
) -> tuple[float, float]:
    """The cheapest standing cylinder over the grid of the module docstring: cost, radius."""
    e1 = np.cross(normal, [1.0, 0.0, 0.0])
    e1 /= np.linalg.norm(e1)
    e2 = np.cross(normal, e1)
    centroid = points.mean(axis=0)
    foot = centroid - (centroid @ normal + offset) * normal
    steps = np.arange(-0.10, 0.1001, 0.004)
    radii = np.arange(0.015, 0.0801, 0.0025)
    a, b, r = (g.reshape(-1) for g in np.meshgrid(steps, steps, radii, indexing="ij"))
    feet = foot + a[:, None] * e1 + b[:, None] * e2
    params = np.column_stack((feet, np.tile(normal, (len(feet), 1)), r))
    model = CylinderModel(with_caps=True)
    best, radius = np.inf, 0.0
    for k in range(0, len(params), 4000):
        cost = _cost(model.distances(params[k : k + 4000], points), threshold)
        j = int(cost.argmin())
        if cost[j] < best:
            best, radius = float(cost[j]), float(params[k + j, 6])
    return best, radius


def object_mask(name: str, label: str, image: np.ndarray) -> np.ndarray:
    """The object's own pixels, flat, as ``measure.object_mask`` takes them on truth.json's
    support."""
    truth = json.loads((SCANS / "truth.json").read_text())[name]["support"]
    normal, offset = np.asarray(truth["normal"]), float(truth["distance_m"])
    return np.asarray(measure.object_mask(name, label, image, normal, offset).reshape(-1))


def relief(name: str, label: str, image: np.ndarray, radius_m: float | None) -> tuple[float, float]:
    """The depth relief across the object's middle rows (the middle third of its first box's
    rows): in each row, the range of the third pixel in from each edge of its own pixels (the
    outline's own two pixels left out) against the nearest in the row; and what a circle would
    give there, of the measured radius or else of half the row's width. Medians over the rows,
    in metres."""
    own = object_mask(name, label, image).reshape(image.shape[:2])
    region = measure.REGIONS[name][1][label][0]
    r0, r1, c0, c1 = region[0] if isinstance(region[0], tuple) else region
    seen, circle = [], []
    for row in range(r0 + (r1 - r0) // 3, r1 - (r1 - r0) // 3):
        cols = np.flatnonzero(own[row, c0:c1]) + c0
        if len(cols) < 8:
            continue
        z, x = image[row, cols, 2], image[row, cols, 0]
        seen.append(float((z[2] + z[-3]) / 2 - z[2:-2].min()))
        r = radius_m if radius_m is not None else float(x[-1] - x[0]) / 2
        dx = np.clip(np.abs(x[[2, -3]] - x[np.argmin(z)]), 0.0, r)
        circle.append(float(np.mean(r - np.sqrt(r**2 - dx**2))))
    return float(np.median(seen)), float(np.median(circle))


def run(name: str, seed: int) -> None:
    truth = json.loads((SCANS / "truth.json").read_text())[name]
    seen: dict[str, Any] = {}
    survey, segment = pipeline.survey, pipeline.segment

    def surveyed(*args: Any, **kwargs: Any) -> Any:
        seen["survey"] = survey(*args, **kwargs)
        return seen["survey"]

    def segmented(*args: Any, **kwargs: Any) -> Any:
        seen["frame"], seen["seg"] = args[0], segment(*args, **kwargs)
        return seen["seg"]

    pipeline.survey, pipeline.segment = surveyed, segmented  # type: ignore[assignment]
    try:
        frame = next(open_source(SCANS / f"{name}.npz"))
        perception = Perception(PerceptionParams(gravity_from_scene=True), seed=seed)
        perception.process(frame)
    finally:
        pipeline.survey, pipeline.segment = survey, segment  # type: ignore[assignment]
    world = seen["frame"].world_from_sensor
    back = np.linalg.inv(world)
    image = measure.points_of(name)
    kept_pixels = np.asarray(frame.pixels)[seen["survey"].keep]
    taken = np.zeros(image.shape[0] * image.shape[1], dtype=bool)
    for plane in seen["survey"].planes:
        taken[kept_pixels[plane.inliers[seen["survey"].voxel_of]]] = True
    kept = np.zeros_like(taken)
    kept[kept_pixels] = True
    clustered = np.zeros_like(taken)
    for each in seen["seg"].clusters:
        clustered[np.asarray(each.pixels)] = True
    for label in ROUND[name]:
        item = truth[label]
        centre = np.asarray(item["centre"])
        own = object_mask(name, label, image)

        def distance(cluster: Any, centre: np.ndarray = centre) -> float:
            return float(np.linalg.norm(back[:3, :3] @ cluster.centroid + back[:3, 3] - centre))

        cluster = min(seen["seg"].clusters, key=distance)
        support = cluster.support or seen["seg"].support
        params = perception.params.fit.for_noise(cluster.noise_m)
        threshold = params.selection_threshold_m
        eye = world[:3, 3]
        fit = fit_cluster(
            cluster.points,
            support=support,
            params=params,
            rng=np.random.default_rng([seed, 0]),
            viewpoint=eye,
        )
        sensor = cluster.points @ back[:3, :3].T + back[:3, 3]
        depths = np.unique(np.round(sensor[:, 2], 4))
        step = float(np.median(np.diff(depths))) if len(depths) > 1 else 0.0
        pixels = np.asarray(cluster.pixels)
        own_kept = own & kept
        share = own_kept.sum()
        elsewhere = (own_kept & clustered).sum() - own_kept[pixels].sum()
        lost = own_kept & ~clustered
        normal = np.asarray(support.normal, dtype=np.float64)
        # The floors are scored on the points the fit scores its candidates on: its sample (the
        # first draw of its generator), when the cluster is larger.
        points = cluster.points
        if len(points) > params.max_fit_points:
            generator = np.random.default_rng([seed, 0])
            draw = generator.choice(len(points), params.max_fit_points, replace=False)
            points = points[np.sort(draw)]
        floor, floor_r = standing_floor(points, normal, support.offset, threshold)
        line = (
            f"{name:15} {label:13} range {np.median(sensor[:, 2]):.2f} m, step "
            f"{1000 * step:4.1f} mm, T {1000 * threshold:4.1f} mm; cluster {len(pixels):4d} pts, "
            f"{own[pixels].mean():.2f} in its box; of the object's: "
            f"{own_kept[pixels].sum() / share:.2f} in it, {elsewhere / share:.2f} in others, "
            f"{(lost & taken).sum() / share:.2f} in a plane, {(lost & ~taken).sum() / share:.2f} "
            "in none"
        )
        bump, round_bump = relief(name, label, image, item.get("radius_m"))
        print(f"{line}; relief {100 * bump:.1f} cm, a circle's {100 * round_bump:.1f} cm")
        if fit is None:
            print("    no fit")
            continue
        prim = fit.primitive
        costs = ", ".join(f"{k.value} {v:.3f}" for k, v in fit.costs.items())
        radius = f" r {100 * prim.radius:.1f} cm" if prim.radius else ""
        measured = ""
        if "radius_m" in item:
            at = world[:3, :3] @ centre + world[:3, 3]
            foot = at - (at @ normal + support.offset) * normal
            truth_cylinder = np.r_[foot, normal, item["radius_m"]][None, :]
            d = CylinderModel(with_caps=True).distances(truth_cylinder, points)
            measured = f"; measured {float(_cost(d[0], threshold)):.3f}"
        ray = cluster.centroid - eye
        ray /= np.linalg.norm(ray)
        offset = np.asarray(prim.centre) - cluster.centroid
        along = float(offset @ ray)
        across = float(np.linalg.norm(offset - along * ray))
        print(
            f"    costs {costs} -> {prim.kind.value}{radius}; standing floor {floor:.3f} "
            f"(r {100 * floor_r:.1f} cm){measured}; centre {100 * along:+.1f} cm along the "
            f"line of sight, {100 * across:.1f} across"
        )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--seed", type=int, default=0, help="the Perception's seed")
    parser.add_argument("--scan", choices=sorted(ROUND), help="one scan only")
    args = parser.parse_args()
    for name in [args.scan] if args.scan else ROUND:
        run(name, args.seed)


if __name__ == "__main__":
    main()
