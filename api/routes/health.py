"""``/health``: is the service up, and which ontology does it hold."""

from typing import Any

from fastapi import APIRouter

from api.deps import StoreDep
from kg import stored_version

router = APIRouter(tags=["health"])


@router.get("/health", summary="Liveness and ontology version")
def health(store: StoreDep) -> dict[str, Any]:
    version = stored_version(store)
    return {
        "status": "ok",
        "ontology_version": version.value if version else None,
        "transactions": store.generation,
    }
