"""The exceptions of the perception package.

ShapesError
├── InvalidCloudError      a point cloud, colour array, depth image or transform is malformed
│                          (also a ValueError)
└── SourceError            a file or bag cannot be read, or holds no usable point cloud
"""

__all__ = ["InvalidCloudError", "ShapesError", "SourceError"]


class ShapesError(Exception):
    """Base of every error the perception package raises on purpose."""


class InvalidCloudError(ShapesError, ValueError):
    """An input array is empty, has the wrong shape, or holds NaN or infinite values."""


class SourceError(ShapesError):
    """A point-cloud file or ROS bag is missing, unreadable, or has no point cloud in it."""
