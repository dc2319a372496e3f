"""Where ROS 1's Python modules come from: Debian's packages, found at run time.

Debian 12 packages ROS Noetic's Python modules (``python3-rospy`` and friends) under
``/usr/lib/python3/dist-packages``, which a virtual environment does not see. That directory
also holds Debian's builds of packages the environment has its own of, or imports optionally
(botocore picks up Debian's pyOpenSSL, which does not work with the environment's cryptography),
so it is not put on the path whole: :func:`load_ros` links ROS's packages, and only those, into
a private directory that it appends to ``sys.path``.
"""

import atexit
import functools
import importlib
import importlib.util
import os
import shutil
import sys
import tempfile
from pathlib import Path

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

SYSTEM_PACKAGES = Path("/usr/lib/python3/dist-packages")
ROS_PYTHON_PACKAGES = (
    "catkin",
    "catkin_pkg",
    "genmsg",
    "genpy",
    "geometry_msgs",
    "roscpp",
    "rosgraph",
    "rosgraph_msgs",
    "roslib",
    "rospkg",
    "rospy",
    "sensor_msgs",
    "std_msgs",
)
"""What rospy, genpy and sensor_msgs import from Debian's directory (PyYAML aside)."""

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
    for path in (*extra, _debian_ros()):
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


@functools.cache
def _debian_ros() -> str:
    """A directory of links to Debian's ROS packages (and PyYAML, if the environment has none)."""
    target = Path(tempfile.mkdtemp(prefix="engram-ros-path-"))
    atexit.register(shutil.rmtree, target, True)
    names = list(ROS_PYTHON_PACKAGES)
    if importlib.util.find_spec("yaml") is None:
        names += ["yaml", *(p.name for p in SYSTEM_PACKAGES.glob("_yaml*"))]
    for name in names:
        source = SYSTEM_PACKAGES / name
        if source.exists():
            (target / name).symlink_to(source)
    return str(target)
