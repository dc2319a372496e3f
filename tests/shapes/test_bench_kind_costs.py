"""``bench/perception_kind_costs.py`` prints each model's final cost on each object's own points,
as ``bench/perception_oracle.py`` fits them, and never loads a held-out scan."""

import json
from pathlib import Path
from types import ModuleType

import numpy as np
import pytest

from tests.shapes.real_scans import SCANS, bench_module

TRUTH = json.loads((SCANS / "truth.json").read_text())
A_HELD_OUT_SCAN = min(
    name for name, scan in TRUTH.items() if scan["held_out"] and not scan.get("reserved")
)
"""Whichever scan is held out at this stop, listed in the bench (the set changes every stop)."""


class Loaded(Exception):
    """Raised instead of loading a scan."""


@pytest.fixture(scope="module")
def kind_costs() -> ModuleType:
    """bench/perception_kind_costs.py as a module."""
    return bench_module("perception_kind_costs")


def test_points_on_one_ray_spread_by_their_depths(kind_costs: ModuleType) -> None:
    """101 points 1 mm apart along the z axis: 90 mm from the 5th to the 95th percentile; the
    same points seen from beside them (across the ray) hardly spread."""
    pts = np.array([[0.0, 0.0, z] for z in np.linspace(1.0, 1.1, 101)])
    assert kind_costs.spread_along_ray_m(pts, np.zeros(3)) == pytest.approx(0.09)
    assert kind_costs.spread_along_ray_m(pts, np.array([5.0, 0.0, 1.05])) < 0.002
    assert kind_costs.spread_along_ray_m(np.zeros((0, 3)), np.zeros(3)) == 0.0


def test_the_mug_s_row_holds_its_fit_and_every_cost(kind_costs: ModuleType) -> None:
    """mug_stereo's mug (a Cylinder in the truth) comes out a Cylinder on its own points, and
    its cylinder costs the least of the four models."""
    (row,) = kind_costs.rows("mug_stereo", draws=1)
    fields = row.split()
    assert fields[:5] == ["mug_stereo", "mug", "Cylinder", "0", "Cylinder"]
    costs = {fields[i]: float(fields[i + 1]) for i in range(5, 13, 2)}
    assert set(costs) == {"Sphere", "Cylinder", "Cone", "Plane"}
    assert min(costs, key=costs.__getitem__) == "Cylinder"


@pytest.mark.parametrize(
    ("scan", "message"),
    [("no_such_scan", "expected one of"), (A_HELD_OUT_SCAN, "held out")],
)
def test_unknown_and_held_out_scans_are_refused_unloaded(
    kind_costs: ModuleType, monkeypatch: pytest.MonkeyPatch, scan: str, message: str
) -> None:
    def refuse(path: object) -> None:
        raise Loaded(Path(str(path)).stem)

    monkeypatch.setattr(kind_costs.oracle, "open_source", refuse)
    monkeypatch.setattr(kind_costs.oracle.measure, "points_of", refuse)
    with pytest.raises(ValueError, match=message):
        kind_costs.rows(scan)
    with pytest.raises(Loaded, match="mug_stereo"):  # the refusal works
        kind_costs.rows("mug_stereo")
