"""``bench/perception.py`` counts a primitive as a part of one measured object at most: the
nearest within 8 cm. One primitive between two objects must not make both found."""

import numpy as np

from tests.shapes.real_scans import bench_module


def test_a_primitive_between_two_objects_is_a_part_of_the_nearer_only() -> None:
    objects = {"dispenser": np.array([0.0, 0.0, 1.0]), "adapter": np.array([0.07, 0.0, 1.0])}
    seen = [np.array([0.02, 0.0, 1.0]), np.array([0.5, 0.0, 1.0])]
    owner = bench_module("perception")._nearest_objects(seen, objects)
    assert owner == ["dispenser", None]  # the adapter is missed; the far primitive is a stray


def test_a_scan_with_no_measured_object_makes_every_primitive_a_stray() -> None:
    assert bench_module("perception")._nearest_objects([np.zeros(3)], {}) == [None]
