"""ARMOR's two ROS services over HTTP, JSON field for field the ROS messages.

``?values=plain`` (IRIs without brackets, bare literal values) or ``?values=short`` (local names)
opts out of ARMOR's string formats for query results.

Directives are many and small, so the request path is kept short:

- a directive that cannot be made to wait runs on the event loop, since it costs less than the
  trip to a worker thread (:meth:`~api.armor.ArmorEngine.execute_now`): a query that reads a few
  triples (every QUERY but QUERY SPARQL; it takes no lock), and a simple write (ADD, REMOVE,
  REPLACE, DISJOINT IND) to a reference that reasons only on REASON, when no other list is
  running and the reference's lock is free. Everything else (SPARQL, REASON, LOAD, SAVE, the
  memory pipeline, lists with writes, any write that might wait) runs in the thread pool, so
  that it never holds up other requests;
- a well-formed request (JSON content type, a body that validates, a valid ``values``, the
  token if one is set) is parsed by pydantic straight from the bytes and answered without
  FastAPI's dependency solving (:class:`_ArmorRoute`); any other request takes FastAPI's usual
  path, so that every error (422, 400, 401) is FastAPI's own;
- the response is written by pydantic once (FastAPI would validate the returned model again).
"""

from collections.abc import Awaitable, Callable, Coroutine
from typing import Annotated, Any, Literal, TypeVar, cast, get_args

from fastapi import APIRouter, Depends, HTTPException, Query, Request, Response
from fastapi.concurrency import run_in_threadpool
from fastapi.routing import APIRoute
from pydantic import BaseModel, ValidationError
from starlette.middleware.body_limit import MAX_BODY_SIZE_SCOPE_KEY

from api.armor import ArmorEngine
from api.armor.models import (
    ArmorDirectiveListReq,
    ArmorDirectiveListRes,
    ArmorRequest,
    ArmorResponse,
)
from api.armor.names import ValueStyle
from api.config import Settings
from api.deps import ArmorDep, require_token

Message = TypeVar("Message", bound=BaseModel)
Handler = Callable[[Request], Coroutine[Any, Any, Response]]
_STYLES = frozenset(get_args(ValueStyle))
_LIST_ON_LOOP = 8
"""Longest list of quick reads answered on the event loop."""


Values = Annotated[
    Literal["armor", "plain", "short"],
    Query(description="How query results are written: ARMOR's strings, plain values, short names"),
]


def _json(message: BaseModel) -> Response:
    return Response(message.model_dump_json(), media_type="application/json")


async def _single(engine: ArmorEngine, body: ArmorRequest, values: ValueStyle) -> Response:
    request = body.armor_request
    response = engine.execute_now(request, style=values)
    if response is None:
        response = await run_in_threadpool(engine.execute, request, style=values)
    return _json(ArmorResponse(armor_response=response))


async def _list(engine: ArmorEngine, body: ArmorDirectiveListReq, values: ValueStyle) -> Response:
    requests = body.armor_requests
    if len(requests) <= _LIST_ON_LOOP and all(engine.is_quick_read(r) for r in requests):
        return _json(engine.execute_list(requests, style=values))
    return _json(await run_in_threadpool(engine.execute_list, requests, style=values))


async def _well_formed(
    request: Request, model: type[Message]
) -> tuple[ArmorEngine, Message, ValueStyle] | None:
    """The engine, body and value style of a request FastAPI would accept as is, else None."""
    content_type = request.headers.get("content-type", "")
    if content_type.partition(";")[0].strip().lower() != "application/json":
        return None
    values = request.query_params.get("values", "armor")
    if values not in _STYLES or MAX_BODY_SIZE_SCOPE_KEY in request.scope:
        return None
    settings: Settings = request.app.state.settings
    if settings.token is not None:
        try:
            await require_token(settings, request.headers.get("authorization"))
        except HTTPException:
            return None
    body = await request.body()
    if not body:
        return None
    try:
        message = model.model_validate_json(body)
    except ValidationError:
        return None
    engine: ArmorEngine = request.app.state.armor
    return engine, message, cast(ValueStyle, values)


def _shortcut(
    model: type[Message], answer: Callable[[ArmorEngine, Message, ValueStyle], Awaitable[Response]]
) -> Callable[[Request], Awaitable[Response | None]]:
    async def shortcut(request: Request) -> Response | None:
        parsed = await _well_formed(request, model)
        return None if parsed is None else await answer(*parsed)

    return shortcut


_SHORTCUTS = {
    "/armor_interface_srv": _shortcut(ArmorRequest, _single),
    "/armor_interface_serialized_srv": _shortcut(ArmorDirectiveListReq, _list),
}


class _ArmorRoute(APIRoute):
    """FastAPI's route, with the shortcut for well-formed requests (see the module docstring)."""

    def get_route_handler(self) -> Handler:
        usual = super().get_route_handler()
        shortcut = _SHORTCUTS.get(self.path)
        if shortcut is None:
            return usual

        async def handler(request: Request) -> Response:
            response = await shortcut(request)
            return response if response is not None else await usual(request)

        return handler


router = APIRouter(tags=["armor"], dependencies=[Depends(require_token)], route_class=_ArmorRoute)


@router.post("/armor_interface_srv", summary="One ARMOR directive", response_model=ArmorResponse)
async def armor_interface_srv(
    body: ArmorRequest, engine: ArmorDep, values: Values = "armor"
) -> Response:
    """``armor_msgs/ArmorDirective``: every protocol outcome, failures included, answers 200."""
    return await _single(engine, body, values)


@router.post(
    "/armor_interface_serialized_srv",
    summary="A list of ARMOR directives",
    response_model=ArmorDirectiveListRes,
)
async def armor_interface_serialized_srv(
    body: ArmorDirectiveListReq, engine: ArmorDep, values: Values = "armor"
) -> Response:
    """``armor_msgs/ArmorDirectiveList``: in order, one transaction, one response each."""
    return await _list(engine, body, values)
