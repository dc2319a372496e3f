"""What ``engram ros`` and ``engram serve --ros`` are asked to run (no ROS import here)."""

from dataclasses import dataclass, field

from shapes import PerceptionParams
from shapes.types import FloatArray

__all__ = ["RosOptions"]


@dataclass(frozen=True)
class RosOptions:
    """The node's name, and the PointCloud2 perception if ``cloud_topic`` is set."""

    node_name: str = "engram"
    cloud_topic: str | None = None
    result_topic: str = "/engram/scenes"
    world_from_sensor: FloatArray | None = None
    perception: PerceptionParams = field(default_factory=PerceptionParams)
    seed: int = 0
    watch_period_s: float = 1.0
