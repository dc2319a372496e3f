"""``/memory/history`` and ``/memory/as-of``: what happened to a class, and what the memory held
at a given time, rebuilt from the history graph (reasoners/history.py). Both only read."""

import datetime as dt
from typing import Annotated, Any

from fastapi import APIRouter, Query, Request
from pyoxigraph import NamedNode

from api.openapi_errors import error_responses
from api.routes.names import memory_iri
from kg.errors import InvalidValueError, NotFoundError
from reasoners import history
from reasoners.errors import UnknownItemError

router = APIRouter(tags=["history"])


@router.get(
    "/memory/history",
    summary="What happened to a learned class or experienced scene, oldest first",
    responses=error_responses(404, 422),
)
def class_history(
    request: Request,
    cls: Annotated[str, Query(alias="class", min_length=1, max_length=2000, examples=["Scene-1"])],
) -> dict[str, Any]:
    """``class`` is a short name in Engram's namespace (``Scene-4``, ``experience-7``) or a full
    IRI. Each event has its ``time`` (ISO 8601, UTC), ``kind`` (learned, reinforced, retrieved,
    rescored, level, forgotten, restored, pinned, unpinned), and the ``score`` (raw score ζ) and
    ``level`` it left (null where there is none). A name the memory never held answers 404."""
    iri = memory_iri(cls, "class")
    memory = request.app.state.services.scene_memory
    events = history.events(memory.store, iri)
    if not events and not _known(memory, iri):
        raise NotFoundError(
            f"class: got {cls!r}, expected a learned class or experienced scene with a history"
        )
    return {"class": iri.value, "events": [e.to_json() for e in events]}


@router.get(
    "/memory/as-of",
    summary="The learned classes that existed at a time, with their levels and scores",
    responses=error_responses(422),
)
def memory_as_of(
    request: Request,
    time: Annotated[str, Query(min_length=1, max_length=64, examples=["2026-01-01T12:00:00Z"])],
) -> dict[str, Any]:
    """``time`` is an ISO 8601 date and time with a time zone (``Z`` or ``+02:00``), or a date
    (its end, UTC). Each class comes with its last event by then and the score (ζ) and level
    that event left."""
    at = _parse_time(time)
    states = history.as_of(request.app.state.services.scene_memory.store, at)
    return {
        "time": at.astimezone(dt.UTC).isoformat(timespec="milliseconds"),
        "classes": [s.to_json() for s in states],
    }


def _parse_time(text: str) -> dt.datetime:
    value = text.strip()
    try:
        if len(value) == 10:  # a date: the end of that day, UTC
            day = dt.date.fromisoformat(value)
            return dt.datetime.combine(day, dt.time(23, 59, 59, 999000), tzinfo=dt.UTC)
        at = dt.datetime.fromisoformat(value)
    except ValueError:
        raise InvalidValueError(
            "time", text, "an ISO 8601 time such as 2026-01-01T12:00:00Z, or a date"
        ) from None
    if at.tzinfo is None:
        raise InvalidValueError(
            "time", text, "a time with a time zone, such as 2026-01-01T12:00:00Z"
        )
    return at


def _known(memory: Any, iri: NamedNode) -> bool:
    """Whether the memory holds ``iri`` live or in the trash (a store older than its history)."""
    if memory.reads.trashed(iri) is not None:
        return True
    try:
        memory.reads.item_scores(iri)
    except UnknownItemError:
        return False
    return True
