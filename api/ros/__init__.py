"""ARMOR's two ROS 1 services, and perception from a ``sensor_msgs/PointCloud2`` topic.

``engram ros`` (or ``engram serve --ros``) registers ``/armor_interface_srv``
(``armor_msgs/ArmorDirective``) and ``/armor_interface_serialized_srv``
(``armor_msgs/ArmorDirectiveList``) with the ROS master named by ``ROS_MASTER_URI``, with ARMOR's
own message definitions (:mod:`api.ros.messages`), so that clients built against ARMOR call
Engram unchanged. See ``docs/ros.md``.

ROS's Python modules (rospy, genpy, ...) come from Debian's packages, outside the virtual
environment: only the modules of this package import them, after :func:`api.ros.system.load_ros`
has put them on the path. Nothing else in Engram needs ROS.
"""
