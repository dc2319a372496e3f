"""ARMOR's two ROS services over HTTP, JSON field for field the ROS messages.

``?values=plain`` (IRIs without brackets, bare literal values) or ``?values=short`` (local names)
opts out of ARMOR's string formats for query results.

Directives are many and small, so the request path is kept short:

- a well-formed request (JSON content type, a body that validates, a valid ``values``, the
  token if one is set) is answered by :mod:`api.fast_armor` ahead of FastAPI's router, with the
  functions below; any other request reaches the routes here, so that every error (422, 400,
  401) is FastAPI's own;
- a directive that cannot be made to wait runs on the event loop, since it costs less than the
  trip to a worker thread (:meth:`~api.armor.ArmorEngine.execute_now`): a query that reads a few
  triples (every QUERY but QUERY SPARQL; it takes no lock), and a simple write (ADD, REMOVE,
  REPLACE, DISJOINT IND) to a reference that reasons only on REASON, when no other list is
  running and the reference's lock is free. Everything else (SPARQL, REASON, LOAD, SAVE, the
  memory pipeline, lists with writes, any write that might wait) runs in the thread pool, so
  that it never holds up other requests;
- the response is written by pydantic once, as bytes (FastAPI would validate the returned model
  again).
"""

from collections.abc import Sequence
from typing import Annotated, Literal

from fastapi import APIRouter, Depends, Query, Response
from fastapi.concurrency import run_in_threadpool

from api.armor import ArmorEngine
from api.armor.models import (
    ArmorDirectiveListReq,
    ArmorDirectiveListRes,
    ArmorDirectiveReq,
    ArmorRequest,
    ArmorResponse,
)
from api.armor.names import ValueStyle
from api.deps import ArmorDep, require_token

__all__ = ["answer_list", "answer_single", "router"]

_LIST_ON_LOOP = 8
"""Longest list of quick reads answered on the event loop."""
_SINGLE_OPEN = b'{"armor_response":'

Values = Annotated[
    Literal["armor", "plain", "short"],
    Query(description="How query results are written: ARMOR's strings, plain values, short names"),
]


async def answer_single(
    engine: ArmorEngine, request: ArmorDirectiveReq, values: ValueStyle
) -> bytes:
    """The JSON body answering one directive (an :class:`ArmorResponse`)."""
    response = engine.execute_now(request, style=values)
    if response is None:
        response = await run_in_threadpool(engine.execute, request, style=values)
    # ArmorResponse(armor_response=response).model_dump_json(), without building the wrapper
    return b"".join((_SINGLE_OPEN, response.__pydantic_serializer__.to_json(response), b"}"))


async def answer_list(
    engine: ArmorEngine, requests: Sequence[ArmorDirectiveReq], values: ValueStyle
) -> bytes:
    """The JSON body answering a list of directives (an :class:`ArmorDirectiveListRes`)."""
    if len(requests) <= _LIST_ON_LOOP and all(engine.is_quick_read(r) for r in requests):
        result = engine.execute_list(requests, style=values)
    else:
        result = await run_in_threadpool(engine.execute_list, requests, style=values)
    return result.__pydantic_serializer__.to_json(result)


def _json(content: bytes) -> Response:
    return Response(content, media_type="application/json")


router = APIRouter(tags=["armor"], dependencies=[Depends(require_token)])


@router.post("/armor_interface_srv", summary="One ARMOR directive", response_model=ArmorResponse)
async def armor_interface_srv(
    body: ArmorRequest, engine: ArmorDep, values: Values = "armor"
) -> Response:
    """``armor_msgs/ArmorDirective``: every protocol outcome, failures included, answers 200."""
    return _json(await answer_single(engine, body.armor_request, values))


@router.post(
    "/armor_interface_serialized_srv",
    summary="A list of ARMOR directives",
    response_model=ArmorDirectiveListRes,
)
async def armor_interface_serialized_srv(
    body: ArmorDirectiveListReq, engine: ArmorDep, values: Values = "armor"
) -> Response:
    """``armor_msgs/ArmorDirectiveList``: in order, one transaction, one response each."""
    return _json(await answer_list(engine, body.armor_requests, values))
