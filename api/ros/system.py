"""Where ROS 1's Python modules come from: Debian's packages, found at run time.

Debian 12 packages ROS Noetic's Python modules (``python3-rospy`` and friends) under
``/usr/lib/python3/dist-packages``, which a virtual environment does not see. :func:`load_ros`
appends that directory to ``sys.path`` (after the environment's own packages, so that none of
them is shadowed) the first time a ROS entry point needs it.
"""

import importlib
import os
import sys

__all__ = ["DEBIAN_PACKAGES", "RosUnavailableError", "load_ros"]

DEBIAN_PACKAGES = (
    "python3-rospy",
    "python3-rosmaster",
    "python3-genpy",
    "python3-genmsg",
    "python3-std-msgs",
    "python3-sensor-msgs",
)
"""What ``engram ros`` needs from apt (scripts/test and scripts/demo install them)."""

_SYSTEM_PATHS = ("/usr/lib/python3/dist-packages",)
_MODULES = ("rospy", "rosgraph", "genpy", "genmsg", "sensor_msgs.msg")


class RosUnavailableError(RuntimeError):
    """ROS 1's Python modules cannot be imported."""


def load_ros() -> None:
    """Make ``rospy``, ``genpy``, ``genmsg`` and ``sensor_msgs`` importable.

    Directories of ``ENGRAM_ROS_PYTHONPATH`` (``os.pathsep``-separated) are tried before
    Debian's. Raises :class:`RosUnavailableError`, naming the Debian packages to install, if a
    module is still missing.
    """
    extra = [p for p in os.environ.get("ENGRAM_ROS_PYTHONPATH", "").split(os.pathsep) if p]
    for path in (*extra, *_SYSTEM_PATHS):
        if os.path.isdir(path) and path not in sys.path:
            sys.path.append(path)
    missing = []
    for name in _MODULES:
        try:
            importlib.import_module(name)
        except ImportError:
            missing.append(name)
    if missing:
        raise RosUnavailableError(
            f"ROS 1: cannot import {', '.join(missing)}; install the Debian packages "
            f"{' '.join(DEBIAN_PACKAGES)} (apt-get install) or set ENGRAM_ROS_PYTHONPATH"
        )
