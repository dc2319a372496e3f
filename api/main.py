"""The FastAPI application over one on-disk store."""

import logging
from collections.abc import AsyncIterator
from contextlib import asynccontextmanager

from fastapi import FastAPI

from api.armor import ArmorEngine
from api.config import Settings, get_settings
from api.errors import install_error_handlers
from api.routes import admin, armor, episodes, export, health, sparql, streams
from episodes import EpisodeMemory
from episodes.streams import RecordingRegistry
from kg import Store, ensure_ontology
from kg.sandbox import QueryRunner

__all__ = ["create_app"]

log = logging.getLogger(__name__)


def create_app(settings: Settings | None = None) -> FastAPI:
    """Build the app; the store opens when it starts and closes when it stops."""
    settings = settings or get_settings()

    @asynccontextmanager
    async def lifespan(app: FastAPI) -> AsyncIterator[None]:
        store = Store(settings.store_dir)
        status = ensure_ontology(store)
        log.info(
            "store %s: ontology %s %s", settings.store_dir, status.version.value, status.action
        )
        runner = QueryRunner(
            store,
            snapshot_dir=settings.snapshot_dir,
            workers=settings.sparql_workers,
            timeout_s=settings.sparql_timeout_s,
            max_result_bytes=settings.sparql_max_result_bytes,
        )
        recordings = RecordingRegistry()
        state = app.state
        state.settings, state.store, state.runner = settings, store, runner
        state.recordings = recordings
        state.armor = ArmorEngine(store)
        state.episodes = EpisodeMemory(store, data_dir=settings.data_dir, recordings=recordings)
        try:
            yield
        finally:
            recordings.close_all()  # a recording still open at shutdown ends as a complete file
            runner.close()
            store.flush()
            # release the store's directory lock
            state.store = state.runner = state.armor = state.episodes = None

    app = FastAPI(
        title="Engram",
        summary="A human-like memory for robots, kept as a knowledge graph",
        version="0.1.0",
        lifespan=lifespan,
    )
    install_error_handlers(app)
    for module in (health, sparql, export, admin, episodes, armor, streams):
        app.include_router(module.router)
    return app
