"""``/health``: is the service up, and which ontology does it hold."""

from typing import Any

from fastapi import APIRouter, Request

from api.deps import StoreDep
from kg import stored_version

router = APIRouter(tags=["health"])


@router.get("/health", summary="Liveness, ontology version and the scene memory's state")
def health(store: StoreDep, request: Request) -> dict[str, Any]:
    """``status`` is "ok", or "loading" while the scene memory opens in the background (SPARQL
    answers meanwhile; memory directives answer exit code 212, "still loading"), or "degraded"
    if opening it failed; ``memory`` says which, and where the memory was read from."""
    version = stored_version(store)
    memory = request.app.state.scene_memory
    if memory.ready:
        state = "ready"
    elif memory.wait_ready(timeout_s=0):
        state = "failed"
    else:
        state = "loading"
    return {
        "status": {"ready": "ok", "loading": "loading", "failed": "degraded"}[state],
        "ontology_version": version.value if version else None,
        "transactions": store.generation,
        "memory": {"state": state, "loaded_from": memory.loaded_from or None},
    }
