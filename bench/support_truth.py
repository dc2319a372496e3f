"""How far the real scans' measured supports can be trusted: the ground truth against itself.

The support of each real scan (``tests/data/real_scans/truth.json``) is a least-squares plane
through the points of a box (or boxes) of bare table or floor chosen by hand
(``tests/data/real_scans/measure.py``). This script fits the same kind of plane through each
half of that box (its top, bottom, left and right halves; where the support is the union of
several small boxes, through the union of all of them but one, for each) and prints, for each
scan, how far those planes lie from the whole box's: the angle between the normals, the
difference of their heights at the camera, and the largest difference of their heights where
the measured objects stand (each object's centre dropped onto the measured plane). Beside them,
the angle the whole box's normal would be uncertain by if its points' spread about the plane
were noise alone (one sigma: the residuals' spread over the root of the points' count times
their smaller spread along the plane).

Where the halves disagree by more than a target, the ground truth cannot tell whether the
pipeline meets it: a floor seen only 1.7 to 2 m away fixes its height at the camera (an
extrapolation over 1.7 m) no better than its tilt, and 0.67 degrees of tilt there is 2 cm. No
part of ``shapes`` runs here, and held-out scans are skipped: only their points are read, but
nothing about them is printed.

    PYTHONPATH=. .venv/bin/python bench/support_truth.py
"""

from __future__ import annotations

import json
import math
import os
from pathlib import Path
from types import ModuleType
from typing import Any

import numpy as np

from tests.shapes.real_scans import load_script

SCANS = Path(__file__).parents[1] / "tests" / "data" / "real_scans"


def _measure() -> ModuleType:
    return load_script(SCANS / "measure.py", "measure")


def _plane(points: np.ndarray) -> tuple[np.ndarray, float]:
    """measure.py's plane: least squares (SVD), the normal towards the camera."""
    centre = points.mean(axis=0)
    normal = np.linalg.svd(points - centre, full_matrices=False)[2][2]
    if normal @ -centre < 0:
        normal = -normal
    return normal, float(-normal @ centre)


Box = tuple[int, int, int, int]


def _parts(support: Any) -> list[tuple[Box, ...]]:
    """The regions whose planes are compared with the whole support's: the four halves of one
    box; of several boxes, every union of all but one."""
    if not isinstance(support[0], tuple):
        r0, r1, c0, c1 = support
        row, col = (r0 + r1) // 2, (c0 + c1) // 2
        halves = [(r0, row, c0, c1), (row, r1, c0, c1), (r0, r1, c0, col), (r0, r1, col, c1)]
        return [(h,) for h in halves]
    return [support[:k] + support[k + 1 :] for k in range(len(support))]


def main() -> None:
    measure = _measure()
    truth = json.loads((SCANS / "truth.json").read_text())
    print(f"load average {os.getloadavg()[0]:.2f}")
    print(
        f"  {'scan':<26}{'support box, m away':>20}{'parts: deg':>13}{'cm at camera':>14}"
        f"{'cm at objects':>15}{'noise alone: deg':>18}"
    )
    for scan, (support, objects) in measure.REGIONS.items():
        if truth[scan].get("held_out"):
            continue
        image = measure.points_of(scan)
        whole = measure.points_in(image, support)
        normal, distance = _plane(whole)
        feet = []
        for label in objects:
            centre = np.asarray(truth[scan][label]["centre"])
            feet.append(centre - (centre @ normal + distance) * normal)
        angle = at_camera = at_objects = 0.0
        for part in _parts(support):
            n, d = _plane(measure.points_in(image, tuple(part)))
            angle = max(angle, math.degrees(math.acos(min(1.0, float(n @ normal)))))
            at_camera = max(at_camera, abs(d - distance))
            at_objects = max([at_objects] + [abs(float(n @ f + d)) for f in feet])
        residual = whole @ normal + distance
        across = whole - whole.mean(axis=0)
        across -= np.outer(across @ normal, normal)
        smaller = np.linalg.eigvalsh(across.T @ across / len(whole))[1]  # [0] is along the normal
        noise_deg = math.degrees(float(residual.std()) / math.sqrt(len(whole) * smaller))
        depth = whole[:, 2]
        print(
            f"  {scan:<26}{f'{depth.min():.2f}-{depth.max():.2f}':>20}{angle:>13.2f}"
            f"{100 * at_camera:>14.1f}{100 * at_objects:>15.1f}{noise_deg:>18.2f}"
        )


if __name__ == "__main__":
    main()
