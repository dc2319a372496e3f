"""Malformed or truncated PLY and PCD files are refused, naming the file and the problem."""

import numpy as np
import open3d as o3d
import pytest

from shapes import SourceError, open_source, read_cloud_file

POINTS = np.random.default_rng(0).random((50, 3))
ASCII_PLY_HEAD = (
    "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
    "property float z\nend_header\n"
)


def _written(tmp_path, suffix, **options):
    path = tmp_path / f"good{suffix}"
    cloud = o3d.geometry.PointCloud(o3d.utility.Vector3dVector(POINTS))
    assert o3d.io.write_point_cloud(str(path), cloud, **options)
    return path.read_bytes()


def _truncated(tmp_path, suffix, **options):
    return _written(tmp_path, suffix, **options)[:-100]


@pytest.mark.parametrize(
    ("name", "content", "message"),
    [
        (
            "short.ply",
            lambda t: _truncated(t, ".ply"),
            r"short.ply': truncated: the header declares 50 vertices \(1200 bytes of data\), "
            r"the file has 1100 bytes",
        ),
        (
            "junk.ply",
            lambda t: (ASCII_PLY_HEAD + "0 0 1\n0 junk 1\n0 0 1\n").encode(),
            r"junk.ply': vertex 1: expected a number, got 'junk'",
        ),
        (
            "extra.ply",
            lambda t: (ASCII_PLY_HEAD + "0 0 1\n0 0 1 7\n0 0 1\n").encode(),
            r"extra.ply': vertex 1: expected 3 values, got 4",
        ),
        (
            "few.ply",
            lambda t: (ASCII_PLY_HEAD + "0 0 1\n").encode(),
            r"few.ply': truncated: the header declares 3 vertices, the body has 1 line",
        ),
        (
            "noz.ply",
            lambda t: (
                b"ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\n"
                b"property float y\nend_header\n0 0\n"
            ),
            r"noz.ply': the vertices have no z property: \['x', 'y'\]",
        ),
        (
            "noend.ply",
            lambda t: b"ply\nformat ascii 1.0\nelement vertex 1\n",
            r"noend.ply': no 'end_header' line",
        ),
        (
            "short.pcd",
            lambda t: _truncated(t, ".pcd"),
            r"short.pcd': truncated: the header declares 50 points \(600 bytes of data\)",
        ),
        (
            "junk.pcd",
            lambda t: _written(t, ".pcd", write_ascii=True).replace(b"\n0.", b"\nx.", 1),
            r"junk.pcd': point 0: expected a number, got 'x\.",
        ),
        (
            "packed.pcd",
            lambda t: _written(t, ".pcd", compressed=True)[:-20],
            r"packed.pcd': truncated: the compressed block has \d+ of its \d+ bytes",
        ),
        (
            "count.pcd",
            lambda t: _written(t, ".pcd").replace(b"POINTS 50", b"POINTS 60"),
            r"count.pcd': POINTS is 60 but WIDTH x HEIGHT is 50 x 1 = 50",
        ),
    ],
)
def test_malformed_cloud_files_are_refused(tmp_path, name, content, message):
    path = tmp_path / name
    path.write_bytes(content(tmp_path))
    with pytest.raises(SourceError, match=message):
        list(open_source(path))


@pytest.mark.parametrize(
    ("suffix", "options"),
    [(".ply", {}), (".ply", {"write_ascii": True}), (".pcd", {}), (".pcd", {"compressed": True})],
)
def test_well_formed_files_are_read_whole(tmp_path, suffix, options):
    path = tmp_path / f"cloud{suffix}"
    path.write_bytes(_written(tmp_path, suffix, **options))
    np.testing.assert_allclose(read_cloud_file(path).points, POINTS, atol=1e-6)


def test_an_organised_pcd_keeps_the_pixel_of_each_point(tmp_path):
    header = (
        "# .PCD v0.7\nVERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\n"
        "WIDTH 2\nHEIGHT 2\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS 4\nDATA ascii\n"
    )
    body = "0 0 1\nnan nan nan\n0.1 0.1 1\n0.2 0.1 1\n"
    path = tmp_path / "organised.pcd"
    path.write_text(header + body)
    frame = read_cloud_file(path)
    assert frame.image_shape == (2, 2)
    assert frame.pixels is not None and frame.pixels.tolist() == [0, 2, 3]
