"""``/export``: the memory as an OWL ontology for Protégé."""

from typing import Annotated, Literal

from fastapi import APIRouter, Query, Response
from starlette.concurrency import run_in_threadpool

from api.deps import StoreDep
from kg.export import DEFAULT_GRAPHS, FORMATS, export

router = APIRouter(tags=["export"])

GraphName = Literal["tbox", "memory", "episodic", "trash", "episodes"]


@router.get("/export", summary="Export graphs as one OWL ontology")
async def export_ontology(
    store: StoreDep,
    format: Literal["rdfxml", "turtle"] = "rdfxml",
    graphs: Annotated[list[GraphName] | None, Query()] = None,
) -> Response:
    """The T-Box and the memory (add ``graphs=episodic`` for experienced scenes) in one file.

    ``graphs`` may repeat (``graphs=tbox&graphs=memory``) or be comma-free single names.
    """
    chosen = list(graphs) if graphs else list(DEFAULT_GRAPHS)
    body = await run_in_threadpool(export, store, chosen, format)
    extension = "owl" if format == "rdfxml" else "ttl"
    return Response(
        body,
        media_type=FORMATS[format][1],
        headers={"Content-Disposition": f'attachment; filename="engram.{extension}"'},
    )
