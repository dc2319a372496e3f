"""The ROS node: ARMOR's two services on the engine, kept registered across master restarts.

Importing this module puts ROS's Python modules on the path (:mod:`api.ros._ros`).
"""

import logging
import threading
from collections.abc import Callable
from typing import Any

from api.armor import ArmorEngine
from api.armor.names import ValueStyle
from api.ros._ros import rosgraph, rospy
from api.ros.convert import request_of, response_to_ros
from api.ros.messages import ArmorMsgs, armor_msgs
from kg import EngramError

__all__ = ["SERIAL_SERVICE", "SERVICE", "ArmorServices", "MasterWatch", "init_node"]

log = logging.getLogger(__name__)

SERVICE = "/armor_interface_srv"
SERIAL_SERVICE = "/armor_interface_serialized_srv"


def init_node(name: str, *, signals: bool) -> None:
    """Register this process with the master of ``ROS_MASTER_URI`` as node ``name``.

    The root logger keeps the handlers it had (``engram serve``'s console); a process that had
    none logs where rospy logs, to its ROS log file (``rospy.loginfo`` also to the console).

    ``signals``: let rospy handle SIGINT/SIGTERM (a process that is only a ROS node); False
    when another framework (uvicorn) owns them, or outside the main thread.
    """
    root = logging.getLogger()
    handlers, level = list(root.handlers), root.level
    rospy.init_node(name, anonymous=False, disable_signals=not signals)
    if handlers:  # rospy replaced the root logger's handlers (uvicorn's) with its log file's
        root.handlers[:] = handlers
        root.setLevel(level)


class ArmorServices:
    """``/armor_interface_srv`` and ``/armor_interface_serialized_srv`` answered by ``engine``.

    A directive's answer is the engine's, as over HTTP (ARMOR's value strings). An input the
    engine refuses as a whole (a list longer than its maximum) or an error of Engram's store is
    answered as a failed service call whose message says why (the client's ServiceException).
    """

    def __init__(
        self,
        engine: ArmorEngine,
        *,
        style: ValueStyle = "armor",
        service: str = SERVICE,
        serial_service: str = SERIAL_SERVICE,
    ) -> None:
        self.engine = engine
        self.style: ValueStyle = style
        self.types: ArmorMsgs = armor_msgs()
        srv = self.types.srv
        self._services = [
            rospy.Service(service, srv.ArmorDirective, self._guarded(self.answer)),
            rospy.Service(serial_service, srv.ArmorDirectiveList, self._guarded(self.answer_list)),
        ]
        log.info("serving %s and %s", service, serial_service)

    @staticmethod
    def _guarded(handler: Callable[[Any], Any]) -> Callable[[Any], Any]:
        def answer(request: Any) -> Any:
            try:
                return handler(request)
            except EngramError as error:  # the client's ServiceException carries the message
                raise rospy.ServiceException(str(error)) from None

        return answer

    def answer(self, request: Any) -> Any:
        """One ``ArmorDirective`` request -> its response."""
        result = self.engine.execute(request_of(request.armor_request), style=self.style)
        return self.types.srv.ArmorDirectiveResponse(
            armor_response=response_to_ros(result, self.types.msg)
        )

    def answer_list(self, request: Any) -> Any:
        """One ``ArmorDirectiveList`` request -> its response (one transaction, see api.armor)."""
        directives = [request_of(one) for one in request.armor_requests]
        result = self.engine.execute_list(directives, style=self.style)
        return self.types.srv.ArmorDirectiveListResponse(
            success=result.success,
            is_consistent=result.is_consistent,
            armor_responses=[response_to_ros(r, self.types.msg) for r in result.armor_responses],
        )

    def shutdown(self) -> None:
        """Unregister both services."""
        for service in self._services:
            service.shutdown("engram stopping")


class MasterWatch:
    """Registers this node's services and topics again when the master restarted.

    rospy registers once, at start; a master that restarts forgets the node. Every
    ``period_s`` this asks the master whether ``probe`` (one of our services) is still ours,
    and if the master answers that it is not, registers every publisher, subscriber and
    service of the node again (subscribers then connect to the topics' current publishers).
    """

    def __init__(self, probe: str = SERVICE, *, period_s: float = 1.0) -> None:
        self.probe = probe
        self.period_s = period_s
        self.reregistrations = 0
        self._master = rosgraph.masterapi.Master(rospy.get_caller_id())
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._run, name="ros-master-watch", daemon=True)
        self._thread.start()

    def _run(self) -> None:
        while not self._stop.wait(self.period_s) and not rospy.is_shutdown():
            try:
                if not self._registered():
                    self._register()
            except OSError:
                continue  # the master is down: try again next period
            except Exception:
                log.exception("could not check the registration with the ROS master")

    def _registered(self) -> bool:
        try:
            uri = self._master.lookupService(self.probe)
        except rosgraph.masterapi.Error:  # the master does not know the service
            return False
        service = rospy.impl.registration.get_service_manager().get_service(self.probe)
        return service is None or uri == service.uri

    def _register(self) -> None:
        """Every registration of this node, again (rospy's RegManager does it once, at start)."""
        master = self._master
        node_uri = rospy.get_node_uri()
        topics = rospy.impl.registration.get_topic_manager()
        services = rospy.impl.registration.get_service_manager()
        for name, data_type in topics.get_publications():
            master.registerPublisher(name, data_type, node_uri)
        for name, data_type in topics.get_subscriptions():
            publishers = master.registerSubscriber(name, data_type, node_uri)
            for listener in rospy.impl.registration.get_registration_listeners().listeners:
                if isinstance(listener, rospy.impl.registration.RegManager):
                    listener.publisher_update(name, publishers)
        for name, service_uri in services.get_services():
            master.registerService(name, service_uri, node_uri)
        self.reregistrations += 1
        log.warning("the ROS master had forgotten this node: registered it again")

    def stop(self) -> None:
        self._stop.set()
        self._thread.join()
