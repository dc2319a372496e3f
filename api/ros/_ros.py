"""ROS 1's Python modules, put on the path first (:func:`api.ros.system.load_ros`): the modules
of this package that talk to ROS import them from here. Raises
:class:`~api.ros.system.RosUnavailableError` on import without them."""

from api.ros.system import load_ros

load_ros()

import rosgraph.masterapi  # noqa: E402
import rospy  # noqa: E402
import rospy.impl.registration  # noqa: E402
import sensor_msgs.msg  # noqa: E402

__all__ = ["rosgraph", "rospy", "sensor_msgs"]
