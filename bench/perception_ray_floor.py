"""Can the cost along the rays tell a far cylinder or cone from the sphere that takes its place?

For one row of ``bench/perception.py`` (``--only``, default the 1.8 m left camera) and one seed,
every cylinder or cone of the scenes whose cluster reaches the rule "Spheres along the rays"
(``shapes.fit.select``: the sphere weighed against its rival along the sensor's rays) is printed
with, along the rays (``shapes.fit.ray.ray_cost``, the cluster's selection threshold):

- ``sphere``: the sphere the rule refines (its cheapest start, as the rule keeps it);
- ``rival``: the rival cylinder or cone, refined from its fit as the rule does;
- ``truth``: the object's own kind at its true parameters, and refined from them (30
  Levenberg-Marquardt steps): the best the rival's refinement could reach from a perfect start;
- ``sphere wins``: whether the rule chooses the sphere, and whether it still would against the
  truth refined (the sphere costs no more than it plus ``tie_margin``);
- ``seen through``: frame points whose ray passes 5 mm or more inside the chosen sphere's
  outline and lies beyond its surface by more than the threshold (the sensor saw past where the
  sphere would be), per point on the sphere's surface; printed for every sphere the rule
  chooses, true spheres included, as a candidate cue.

The figures are the floor of any rule that compares the costs along the rays: if the sphere
wins against the truth refined, no better start for the rival can end the swap.

Run from the repository root::

    PYTHONPATH=. .venv/bin/python bench/perception_ray_floor.py --seed 20261123
"""

import argparse
import math
import os

for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import numpy as np  # noqa: E402

import shapes.fit.select as select  # noqa: E402
import shapes.pipeline as pipeline  # noqa: E402
from bench.perception import CONDITIONS  # noqa: E402
from shapes.fit.models import ConeModel, CylinderModel, SphereModel  # noqa: E402
from shapes.fit.ray import ray_cost, ray_errors, refine_on_rays  # noqa: E402
from shapes.synthetic import TruthObject  # noqa: E402

TIE = select.FitParams().tie_margin


def truth_model(obj: TruthObject) -> tuple[CylinderModel | ConeModel, np.ndarray] | None:
    """The model and parameters of a true cylinder or cone (None for other kinds)."""
    up = obj.rotation @ np.array([0.0, 0.0, 1.0])
    base = np.asarray(obj.position, dtype=np.float64)
    if obj.kind == "Cylinder":
        return CylinderModel(), np.concatenate((base, up, [obj.radius]))
    if obj.kind == "Cone":
        apex = base + up * obj.height
        return ConeModel(), np.concatenate((apex, -up, [math.atan(obj.radius / obj.height)]))
    return None


def seen_through(ball: np.ndarray, world: np.ndarray, eye: np.ndarray, threshold: float) -> float:
    """Frame points seen past the sphere (module docstring) per point on its surface."""
    e = ray_errors(SphereModel(), ball[None, :], world, eye)[0]
    rays = world - eye
    rays /= np.linalg.norm(rays, axis=1)[:, None]
    to_centre = ball[:3] - eye
    along = rays @ to_centre
    off_axis = np.sqrt(np.maximum(to_centre @ to_centre - along**2, 0.0))
    past = np.isfinite(e) & (e > threshold) & (off_axis < ball[3] - 0.005)
    on = np.isfinite(e) & (np.abs(e) <= threshold)
    return float(past.sum() / max(int(on.sum()), 1))


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--seed", type=int, default=20261123)
    ap.add_argument("--only", default="3 mm, 1.8 m left")
    args = ap.parse_args()
    seen: list[dict[str, object]] = []
    frame_world: list[np.ndarray] = []
    weigh = select._sphere_on_rays
    segment = pipeline.segment

    def recorded(sphere, rival, params, sample, eye, models, fp, within, up=None, others=None):  # type: ignore[no-untyped-def]
        ball = weigh(sphere, rival, params, sample, eye, models, fp, within, up, others)
        t = fp.selection_threshold_m
        model = models[rival][0]
        rival_refined = refine_on_rays(
            model, params, sample, eye, threshold=t, iterations=fp.ray_iterations
        )
        rival_cost = min(
            ray_cost(model, x, sample, eye, threshold=t) for x in (params, rival_refined)
        )
        seen.append(
            {
                "centre": sample.mean(axis=0),
                "sample": sample,
                "eye": eye,
                "t": t,
                "rival": rival.value,
                "rival_cost": rival_cost,
                "ball": ball,
                "sphere_cost": None
                if ball is None
                else ray_cost(models[select.ShapeKind.SPHERE][0], ball, sample, eye, threshold=t),
                "through": None if ball is None else seen_through(ball, frame_world[-1], eye, t),
            }
        )
        return ball

    def segment_recorded(frame, *a, **k):  # type: ignore[no-untyped-def]
        frame_world.append(frame.world_points())
        return segment(frame, *a, **k)

    select._sphere_on_rays = recorded  # type: ignore[assignment]
    pipeline.segment = segment_recorded  # type: ignore[assignment]
    print(f"seed {args.seed}, tie margin {TIE}; costs along the rays")
    print(
        f"{'row':24s} {'scene':>5s} {'object':28s} {'rival':8s} {'sphere':>6s} {'rival':>6s} "
        f"{'truth':>6s} {'refined':>7s} {'sphere wins':>17s} {'seen through':>12s}"
    )
    floor = swaps = 0
    for cond in CONDITIONS:
        if args.only not in cond.name:
            continue
        for i in range(12 * cond.scene_factor):
            rng = np.random.default_rng([args.seed, i, len(cond.name)])
            scene = cond.scene(rng)
            shot = cond.camera.shoot(scene, rng, cond.sensor, cond.room)
            seen.clear()
            pipeline.Perception(seed=i).process(shot.frame)
            for obj in scene.objects:
                truth = truth_model(obj)
                if truth is None:
                    continue
                mid = np.asarray(obj.position) + obj.rotation @ np.array([0, 0, obj.height / 2])
                for r in seen:
                    if np.linalg.norm(np.asarray(r["centre"]) - mid) > 0.08:
                        continue
                    model, x = truth
                    sample, eye, t = r["sample"], r["eye"], float(r["t"])  # type: ignore[arg-type]
                    at_truth = ray_cost(model, x, sample, eye, threshold=t)  # type: ignore[arg-type]
                    y = refine_on_rays(model, x, sample, eye, threshold=t, iterations=30)  # type: ignore[arg-type]
                    refined = min(at_truth, ray_cost(model, y, sample, eye, threshold=t))  # type: ignore[arg-type]
                    won = r["ball"] is not None
                    cost = r["sphere_cost"]
                    still = won and cost is not None and float(cost) <= refined + TIE  # type: ignore[arg-type]
                    swaps += won
                    floor += still
                    name = f"{obj.kind} r {obj.radius * 100:.1f} h {obj.height * 100:.1f} cm"
                    sphere = "-" if cost is None else f"{float(cost):.3f}"  # type: ignore[arg-type]
                    through = "-" if r["through"] is None else f"{float(r['through']):.2f}"  # type: ignore[arg-type]
                    print(
                        f"{cond.name:24s} {i:5d} {name:28s} {r['rival']!s:8s} {sphere:>6s} "
                        f"{float(r['rival_cost']):6.3f} {at_truth:6.3f} {refined:7.3f} "  # type: ignore[arg-type]
                        f"{str(won) + ' / ' + str(still):>17s} {through:>12s}"
                    )
            for r in seen:
                if r["ball"] is not None and r["through"] is not None:
                    near = min(
                        scene.objects,
                        key=lambda o: float(
                            np.linalg.norm(np.asarray(o.position) - np.asarray(r["centre"]))
                        ),
                    )
                    if near.kind == "Sphere":
                        label = f"Sphere r {near.radius * 100:.1f} cm"
                        print(
                            f"{cond.name:24s} {i:5d} {label:28s} "
                            f"{r['rival']!s:8s} {float(r['sphere_cost']):6.3f} "  # type: ignore[arg-type]
                            f"{float(r['rival_cost']):6.3f} {'':6s} {'':7s} {'True':>17s} "  # type: ignore[arg-type]
                            f"{float(r['through']):12.2f}"  # type: ignore[arg-type]
                        )
    print(
        f"cylinders and cones taken for spheres: {swaps}; of them the sphere still wins against "
        f"the truth refined along the rays: {floor}"
    )


if __name__ == "__main__":
    main()
