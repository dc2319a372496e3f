"""ARMOR's two ROS services over HTTP, JSON field for field the ROS messages.

``?values=plain`` (IRIs without brackets, bare literal values) or ``?values=short`` (local names)
opts out of ARMOR's string formats for query results.
"""

from typing import Annotated, Literal

from fastapi import APIRouter, Depends, Query

from api.armor.models import (
    ArmorDirectiveListReq,
    ArmorDirectiveListRes,
    ArmorRequest,
    ArmorResponse,
)
from api.deps import ArmorDep, require_token

router = APIRouter(tags=["armor"], dependencies=[Depends(require_token)])

Values = Annotated[
    Literal["armor", "plain", "short"],
    Query(description="How query results are written: ARMOR's strings, plain values, short names"),
]


@router.post("/armor_interface_srv", summary="One ARMOR directive")
def armor_interface_srv(
    body: ArmorRequest, engine: ArmorDep, values: Values = "armor"
) -> ArmorResponse:
    """``armor_msgs/ArmorDirective``: every protocol outcome, failures included, answers 200."""
    return ArmorResponse(armor_response=engine.execute(body.armor_request, style=values))


@router.post("/armor_interface_serialized_srv", summary="A list of ARMOR directives")
def armor_interface_serialized_srv(
    body: ArmorDirectiveListReq, engine: ArmorDep, values: Values = "armor"
) -> ArmorDirectiveListRes:
    """``armor_msgs/ArmorDirectiveList``: in order, one transaction, one response each."""
    return engine.execute_list(body.armor_requests, style=values)
