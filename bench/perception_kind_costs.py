"""Why an object gets its kind: each model's final cost on the object's own points.

For every real scan tuned on (the held-out and reserved ones, ``"held_out": true`` in truth.json,
are never loaded) and every measured object the ground truth gives a kind (``--all``: every
measured object), the object's own points are fitted as ``bench/perception_oracle.py`` fits them
(:func:`own_points` there: the ground truth's pixels the survey keeps, gravity and the support
from the measured support, the camera as the viewpoint, the generator of draw k). A row per draw
gives the kind chosen, each model's final cost (``ClusterFit.costs``: the truncated quadratic
cost on the fit's sample, before the parameter charge; a model missing from it left the running
before the choice), the selection threshold, the points' median depth, and how far they spread
along the mean ray (5th to 95th percentile: a standing cylinder's visible front spans at most
its radius, plus the noise). ``--charge`` sets ``FitParams.parameter_charge`` (the charge the
planes and the best curved model pay for their parameters when they meet).

Run from the repository root (under a minute of CPU)::

    PYTHONPATH=. .venv/bin/python bench/perception_kind_costs.py
    PYTHONPATH=. .venv/bin/python bench/perception_kind_costs.py --scan desk_tum --draws 3
"""

import os

for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import argparse  # noqa: E402
import json  # noqa: E402
import platform  # noqa: E402
from dataclasses import replace  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402
import numpy.typing as npt  # noqa: E402

from shapes import PerceptionParams, ShapeKind  # noqa: E402
from shapes.fit import fit_cluster  # noqa: E402
from tests.shapes.real_scans import load_script  # noqa: E402

oracle = load_script(Path(__file__).with_name("perception_oracle.py"), "perception_oracle")
KINDS = (ShapeKind.SPHERE, ShapeKind.CYLINDER, ShapeKind.CONE, ShapeKind.PLANE)


def spread_along_ray_m(world: npt.NDArray[np.float64], eye: npt.NDArray[np.float64]) -> float:
    """How far ``world``'s points spread along their mean ray from ``eye``: the 5th to the 95th
    percentile of their depths along it (m); 0 for no points.

    >>> pts = np.array([[0.0, 0.0, z] for z in np.linspace(1.0, 1.1, 101)])
    >>> round(spread_along_ray_m(pts, np.zeros(3)), 3)
    0.09
    """
    if not len(world):
        return 0.0
    rays = world - eye
    mean = rays.mean(axis=0)
    depth = rays @ (mean / np.linalg.norm(mean))
    return float(np.percentile(depth, 95) - np.percentile(depth, 5))


def rows(
    scan: str, *, draws: int = 3, charge: float | None = None, every_object: bool = False
) -> list[str]:
    """One line per object and draw of tuned-on ``scan`` (module docstring).

    Raises ValueError when ``scan`` is not a real scan the bench lists, or is held out."""
    truth = json.loads((oracle.SCANS / "truth.json").read_text())
    measured = oracle.bench.REAL_TRUTH.get(scan)
    if measured is None:
        raise ValueError(f"scan: expected one of {sorted(oracle.bench.REAL_TRUTH)}, got {scan!r}")
    gt = truth[measured]
    if gt.get("held_out") or gt.get("reserved"):
        raise ValueError(f"scan: {scan!r} is held out; it is never loaded here")
    frame = next(oracle.open_source(oracle.SCANS / f"{scan}.npz"))
    support_plane = oracle.measured_support(scan, measured)
    objects, support, pose = oracle.own_points(
        frame, oracle.object_pixels(scan, measured), support_plane
    )
    params = PerceptionParams(gravity_from_scene=True).fit
    if charge is not None:
        params = replace(params, parameter_charge=charge)
    out = []
    for label, own in objects.items():
        kind = gt[label].get("kind")
        if kind is None and not every_object:
            continue
        fp = params.for_noise(own.noise_m)
        eye = pose[:3, 3]
        spread = spread_along_ray_m(own.world, eye)
        # The sensor's depths (the noise is taken at their median): world = sensor @ R.T.
        depth = float(np.median((own.world @ pose[:3, :3])[:, 2])) if len(own.world) else 0.0
        for draw in range(draws):
            fit = fit_cluster(
                own.world,
                support=support,
                params=fp,
                rng=np.random.default_rng([draw, 0]),
                viewpoint=eye,
            )
            got = "none" if fit is None else fit.primitive.kind.value
            costs = (
                ""
                if fit is None
                else "  ".join(
                    f"{k.value} {fit.costs[k]:.3f}" if k in fit.costs else f"{k.value} -"
                    for k in KINDS
                )
            )
            out.append(
                f"  {scan:<28}{label:<26} {kind or '-':<9}{draw:>4}  {got:<10}{costs:<62}"
                f"T {1000 * fp.selection_threshold_m:4.1f} mm  {depth:4.2f} m  "
                f"{100 * spread:4.1f} cm  {len(own.world)}"
            )
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--scan", action="append", help="only this tuned-on scan (repeatable)")
    parser.add_argument("--draws", type=int, default=3, help="the fit's generators (3)")
    parser.add_argument("--charge", type=float, help="FitParams.parameter_charge (default 1)")
    parser.add_argument("--all", action="store_true", help="every measured object, kind or not")
    args = parser.parse_args()
    if hasattr(os, "sched_setaffinity"):
        os.sched_setaffinity(0, {min(os.sched_getaffinity(0))})
    print("perception kind costs: each model's final cost on each object's own points")
    print(
        f"machine: {platform.machine()}, load average {os.getloadavg()[0]:.2f}; "
        f"python {platform.python_version()}"
    )
    scans = args.scan or [scan for scan, _ in oracle.bench.loadable_scans()]
    print(
        f"  {'scan':<28}{'object':<26} {'kind':<9}{'draw':>4}  {'fitted':<10}{'final costs':<62}"
        "threshold  depth  along the ray  points"
    )
    for scan in scans:
        for line in rows(scan, draws=args.draws, charge=args.charge, every_object=args.all):
            print(line, flush=True)


if __name__ == "__main__":
    main()
