"""``/health``: is the service up, and which ontology does it hold."""

from typing import Any

from fastapi import APIRouter, Request

from api.deps import StoreDep

router = APIRouter(tags=["health"])


@router.get("/health", summary="Liveness, ontology version and the scene memory's state")
async def health(store: StoreDep, request: Request) -> dict[str, Any]:
    """``status`` is "ok", or "loading" while the scene memory opens in the background (SPARQL
    answers meanwhile; memory directives answer exit code 212, "still loading"), or "degraded"
    if opening it failed; ``memory`` says which, and where the memory was read from.

    Answered on the event loop from what the server holds in memory (the ontology version that
    opening the store ensured, the store's transaction count, the memory's state), never from
    the store, so that it stays quick beside busy writers and readers."""
    services = request.app.state.services
    version = services.ontology.version
    memory = services.scene_memory
    if memory.loaded.ready:
        state = "ready"
    elif memory.loaded.wait_ready(timeout_s=0):
        state = "failed"
    else:
        state = "loading"
    return {
        "status": {"ready": "ok", "loading": "loading", "failed": "degraded"}[state],
        "ontology_version": version.value if version else None,
        "transactions": store.generation,
        "memory": {"state": state, "loaded_from": memory.loaded.source or None},
    }
