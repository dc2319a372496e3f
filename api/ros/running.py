"""A running ROS node: the services, the optional perception, the master watch.

Importing this module puts ROS's Python modules on the path (:mod:`api.ros._ros`).
"""

import logging

from api.armor import ArmorEngine
from api.ros._ros import rospy
from api.ros.node import ArmorServices, MasterWatch, init_node
from api.ros.node_options import RosOptions
from api.ros.perception import CloudPerception
from shapes import Perception

__all__ = ["RunningNode"]

log = logging.getLogger(__name__)


class RunningNode:
    """Registers node ``options.node_name`` and starts what ``options`` ask for, on ``engine``.

    ``signals``: rospy handles SIGINT/SIGTERM (True only in a process that is just the node,
    from its main thread).
    """

    def __init__(self, engine: ArmorEngine, options: RosOptions, *, signals: bool) -> None:
        init_node(options.node_name, signals=signals)
        self.services = ArmorServices(engine)
        self.perception: CloudPerception | None = None
        if options.cloud_topic is not None:
            self.perception = CloudPerception(
                engine,
                topic=options.cloud_topic,
                result_topic=options.result_topic,
                perception=Perception(options.perception, seed=options.seed),
                world_from_sensor=options.world_from_sensor,
            )
        self.watch = MasterWatch(period_s=options.watch_period_s)

    @staticmethod
    def spin() -> None:
        """Block until rospy shuts down (SIGINT, SIGTERM, or :meth:`stop` elsewhere)."""
        rospy.spin()

    def stop(self) -> None:
        """Unregister everything and shut rospy down (once per process: a node cannot restart)."""
        self.watch.stop()
        if self.perception is not None:
            self.perception.stop()
        self.services.shutdown()
        rospy.signal_shutdown("engram stopping")
