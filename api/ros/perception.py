"""Perception from a ``sensor_msgs/PointCloud2`` topic: stable scenes into the memory, and what
the memory made of each on a result topic.

The subscriber keeps only the newest cloud: while one is being perceived, a newer one replaces
any that waited, so a sensor faster than perception costs skipped frames, never a growing
backlog. Each stable scene is stored as ``engram perceive`` stores it (one directive list:
``LOAD INIT``, the primitives' ``ADD``\\ s, ``SCENE UPDATED``), and the answer of that list's last
directive is published as an ``armor_msgs/ArmorDirectiveRes``: ``queried_objects[0]`` is the
class the scene was stored under, ``sparql_queried_objects`` the memory's details (``learned``,
``confidence``, ...). A list the memory refused publishes its failing directive's answer.

The pose is a parameter: ``world_from_sensor``, the 4x4 matrix taking the cloud's points to a
world frame whose z axis points up, against gravity (identity: the cloud is already in such a
frame). Importing this module puts ROS's Python modules on the path (:mod:`api.ros._ros`).
"""

import collections
import logging
import threading
import time
from dataclasses import dataclass
from typing import Any

import numpy as np

from api.armor import ArmorEngine
from api.client import scene_directives
from api.perceive import scene_primitives
from api.protocol import ArmorDirectiveReq, ArmorDirectiveRes
from api.ros._ros import rospy, sensor_msgs
from api.ros.convert import response_to_ros
from api.ros.latest import Latest
from api.ros.messages import armor_msgs
from shapes import Frame, Perception, ShapesError, StableScene
from shapes.bags import decode_pointcloud2_pixels
from shapes.types import FloatArray

__all__ = ["CloudPerception", "PerceptionCounts", "frame_of"]

log = logging.getLogger(__name__)

_BUFFER_BYTES = 1 << 26
"""rospy's receive buffer: a 640x480 cloud of 32-byte points is about 10 MB."""


def frame_of(message: Any, world_from_sensor: FloatArray | None = None) -> Frame | None:
    """The points (and packed colours) of a PointCloud2 as a frame, organised (``height`` > 1:
    with its image shape and pixels, for the artefact filters) or not; None for a cloud with no
    finite point. Raises :class:`shapes.SourceError` for an unreadable one."""
    points, colours, pixels = decode_pointcloud2_pixels(message)
    if len(points) == 0:
        return None
    stamp = message.header.stamp.to_sec()
    pose = np.eye(4) if world_from_sensor is None else world_from_sensor
    rows, columns = int(message.height), int(message.width)
    if rows <= 1:
        return Frame(points, colours, stamp, message.header.frame_id, pose)
    return Frame(points, colours, stamp, message.header.frame_id, pose, (rows, columns), pixels)


@dataclass
class PerceptionCounts:
    """What the subscriber did so far."""

    received: int = 0
    perceived: int = 0
    skipped: int = 0
    """Clouds replaced by a newer one before perception reached them."""
    refused: int = 0
    """Clouds that could not be read (bad fields, short data)."""
    scenes: int = 0
    """Stable scenes stored (or refused by the memory: see the published answers)."""


class CloudPerception:
    """Subscribes to ``topic``, perceives in a worker thread, publishes on ``result_topic``."""

    def __init__(
        self,
        engine: ArmorEngine,
        *,
        topic: str,
        result_topic: str,
        perception: Perception | None = None,
        world_from_sensor: FloatArray | None = None,
        client_name: str = "perception",
        reference_name: str = "engram",
    ) -> None:
        self.engine = engine
        self.perception = perception or Perception()
        self.world_from_sensor = world_from_sensor
        self.client_name, self.reference_name = client_name, reference_name
        self.counts = PerceptionCounts()
        self.durations_s: collections.deque[float] = collections.deque(maxlen=1000)
        """How long perceiving (and storing) each of the last clouds took."""
        self._msg = armor_msgs().msg
        self._clouds: Latest[Any] = Latest()
        self._counting = threading.Lock()
        self.publisher = rospy.Publisher(result_topic, self._msg.ArmorDirectiveRes, queue_size=10)
        self._worker = threading.Thread(target=self._run, name="ros-perception", daemon=True)
        self._worker.start()
        self.subscriber = rospy.Subscriber(
            topic,
            sensor_msgs.msg.PointCloud2,
            self._received,
            queue_size=1,
            buff_size=_BUFFER_BYTES,
        )
        log.info("perceiving %s, publishing scenes on %s", topic, result_topic)

    def _received(self, message: Any) -> None:
        with self._counting:  # rospy calls back from one thread per publisher
            self.counts.received += 1
            self.counts.skipped += self._clouds.put(message)

    def _run(self) -> None:
        while (message := self._clouds.take()) is not None:
            started = time.perf_counter()
            try:
                self._perceive(message)
            except Exception:  # one bad cloud or store error must not end the subscriber
                log.exception("perceiving a cloud failed")
            self.durations_s.append(time.perf_counter() - started)

    def _perceive(self, message: Any) -> None:
        try:
            frame = frame_of(message, self.world_from_sensor)
        except ShapesError as error:
            self.counts.refused += 1
            log.warning("skipping a cloud on %s: %s", self.subscriber.resolved_name, error)
            return
        self.counts.perceived += 1
        if frame is None:
            return
        for event in self.perception.process(frame).events:
            if isinstance(event, StableScene) and event.primitives:
                answer = self.store(event)
                self.counts.scenes += 1
                self.publisher.publish(response_to_ros(answer, self._msg))

    def store(self, scene: StableScene) -> ArmorDirectiveRes:
        """Store one scene as one directive list; the answer of its last directive, or of the
        first that failed (the list then changed nothing)."""
        directives = scene_directives(scene_primitives(scene))
        result = self.engine.execute_list(
            [
                ArmorDirectiveReq(
                    client_name=self.client_name,
                    reference_name=self.reference_name,
                    command=command,
                    primary_command_spec=first,
                    secondary_command_spec=second,
                    args=args,
                )
                for command, first, second, args in directives
            ]
        )
        for response in result.armor_responses:
            if not response.success and response.exit_code != 0:
                return response
        answer: ArmorDirectiveRes = result.armor_responses[-1]
        log.info("scene stored as %s", answer.queried_objects[:1])
        return answer

    def stop(self) -> None:
        """Unsubscribe and end the worker (after the cloud it is perceiving)."""
        self.subscriber.unregister()
        self._clouds.close()
        self._worker.join()
        self.publisher.unregister()
