"""The exceptions of the perception package.

EngramError (kg), each error also of kg.errors' kind InvalidInputError
└── ShapesError
    ├── InvalidCloudError      a point cloud, colour array, depth image or transform is malformed
    └── SourceError            a file or bag cannot be read, or holds no usable point cloud
"""

from kg.errors import EngramError, InvalidInputError

__all__ = ["InvalidCloudError", "ShapesError", "SourceError"]


class ShapesError(EngramError):
    """Base of every error the perception package raises on purpose."""


class InvalidCloudError(ShapesError, InvalidInputError):
    """An input array is empty, has the wrong shape, or holds NaN or infinite values."""


class SourceError(ShapesError, InvalidInputError):
    """A point-cloud file or ROS bag is missing, unreadable, or has no point cloud in it."""
