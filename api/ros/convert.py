"""ROS messages of ``armor_msgs`` to and from the engine's models, field for field.

The ROS side is duck-typed (genpy's classes): these functions need only their attributes, and
the ROS classes to build are passed in.
"""

from collections.abc import Sequence
from typing import Any

from api.protocol import ArmorDirectiveReq, ArmorDirectiveRes, QueryItem

__all__ = ["request_of", "response_of", "response_to_ros", "ros_request"]


def request_of(message: Any) -> ArmorDirectiveReq:
    """An ``armor_msgs/ArmorDirectiveReq`` as the engine's model."""
    return ArmorDirectiveReq(
        client_name=message.client_name,
        reference_name=message.reference_name,
        command=message.command,
        primary_command_spec=message.primary_command_spec,
        secondary_command_spec=message.secondary_command_spec,
        args=list(message.args),
    )


def ros_request(request: ArmorDirectiveReq, msg: Any) -> Any:
    """The engine's model as an ``armor_msgs/ArmorDirectiveReq`` (``msg``: ``armor_msgs.msg``)."""
    return msg.ArmorDirectiveReq(
        client_name=request.client_name,
        reference_name=request.reference_name,
        command=request.command,
        primary_command_spec=request.primary_command_spec,
        secondary_command_spec=request.secondary_command_spec,
        args=list(request.args),
    )


def response_to_ros(response: ArmorDirectiveRes, msg: Any) -> Any:
    """The engine's answer as an ``armor_msgs/ArmorDirectiveRes`` (``msg``: ``armor_msgs.msg``)."""
    return msg.ArmorDirectiveRes(
        success=response.success,
        timeout=response.timeout,
        exit_code=response.exit_code,
        error_description=response.error_description,
        is_consistent=response.is_consistent,
        queried_objects=list(response.queried_objects),
        sparql_queried_objects=_items(response.sparql_queried_objects, msg),
    )


def _items(items: Sequence[QueryItem], msg: Any) -> list[Any]:
    return [msg.QueryItem(key=item.key, value=item.value) for item in items]


def response_of(message: Any) -> ArmorDirectiveRes:
    """An ``armor_msgs/ArmorDirectiveRes`` as the engine's model."""
    return ArmorDirectiveRes(
        success=message.success,
        timeout=message.timeout,
        exit_code=message.exit_code,
        error_description=message.error_description,
        is_consistent=message.is_consistent,
        queried_objects=list(message.queried_objects),
        sparql_queried_objects=[
            QueryItem(key=item.key, value=item.value) for item in message.sparql_queried_objects
        ],
    )
