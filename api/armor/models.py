"""The ROS messages of ``armor_msgs`` as JSON models: they live in :mod:`api.protocol`, which
the robot-side client imports without the server; re-exported here for the engine."""

from api.protocol import (
    ArmorDirectiveListReq,
    ArmorDirectiveListRes,
    ArmorDirectiveReq,
    ArmorDirectiveRes,
    ArmorRequest,
    ArmorResponse,
    QueryItem,
)

__all__ = [
    "ArmorDirectiveListReq",
    "ArmorDirectiveListRes",
    "ArmorDirectiveReq",
    "ArmorDirectiveRes",
    "ArmorRequest",
    "ArmorResponse",
    "QueryItem",
]
