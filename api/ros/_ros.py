"""ROS 1's Python modules, put on the path first (:func:`api.ros.system.load_ros`): the modules
of this package that talk to ROS import them from here. Raises
:class:`~api.ros.system.RosUnavailableError` on import without them.

Importing rosgraph makes its ``RospyLogger`` the class of every logger created afterwards
(``logging.setLoggerClass``); the previous class is restored, so that only ROS's own loggers
are rospy's.
"""

import logging

from api.ros.system import load_ros

_logger_class = logging.getLoggerClass()
load_ros()

import rosgraph.masterapi  # noqa: E402
import rosgraph.network  # noqa: E402
import rosgraph.roslogging  # noqa: E402
import rospy  # noqa: E402
import rospy.impl.registration  # noqa: E402
import sensor_msgs.msg  # noqa: E402

logging.setLoggerClass(_logger_class)

__all__ = ["rosgraph", "rospy", "sensor_msgs"]
