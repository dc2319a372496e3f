"""The FastAPI application over one on-disk store."""

import asyncio
import gc
import logging
from collections.abc import AsyncIterator
from contextlib import asynccontextmanager

from fastapi import FastAPI
from starlette.concurrency import run_in_threadpool

from api import security
from api.config import Settings, get_settings
from api.errors import install_error_handlers
from api.openapi_errors import install_error_docs
from api.routes import admin, armor, ask, episodes, export, health, history, sparql, streams, views
from api.services import Services, announce_server, open_services
from api.telemetry import fastapi_telemetry
from reasoners.clock import SettableClock
from reasoners.memory import SceneMemory

__all__ = ["create_app"]

log = logging.getLogger(__name__)


async def _upkeep(services: Services, period_s: float) -> None:
    """:meth:`Services.upkeep` every ``period_s``, in a worker thread."""
    while True:
        await asyncio.sleep(period_s)
        await run_in_threadpool(services.upkeep)


async def _freeze_once_loaded(memory: SceneMemory, poll_s: float = 0.5) -> None:
    """Once the scene memory has loaded, hand the process's heap so far (the memory model
    above all: millions of objects at 100,000 classes) to the collector's permanent generation
    (``gc.freeze``), so that its full collections stop walking it during updates. Unfrozen at
    shutdown (bench/README.md has what it saves)."""
    while not memory.loaded.wait_ready(timeout_s=0):
        await asyncio.sleep(poll_s)
    gc.freeze()


def _local_url(settings: Settings) -> str:
    """The URL a process on this machine reaches the server at."""
    host = "127.0.0.1" if settings.host in ("0.0.0.0", "::") else settings.host
    return f"http://{host}:{settings.port}"


def create_app(settings: Settings | None = None) -> FastAPI:
    """Build the app; the store opens when it starts and closes when it stops."""
    settings = settings or get_settings()

    @asynccontextmanager
    async def lifespan(app: FastAPI) -> AsyncIterator[None]:
        clock = SettableClock() if settings.clock_settable else None
        # the scene memory opens in the background (its index file, or a rebuild from the
        # store): /health and SPARQL answer meanwhile, memory directives answer "loading".
        # `engram serve` refuses a damaged store before this (reasoners.check)
        services = open_services(settings, create=True, clock=clock, background=True, serving=True)
        log.info(
            "store %s: ontology %s %s",
            services.where,
            services.ontology.version.value,
            services.ontology.action,
        )
        app.state.services = services
        scene_memory = services.scene_memory
        services.runner  # noqa: B018 - the query workers start with the server, not on a first query
        withdraw = (
            announce_server(settings.data_dir, _local_url(settings))
            if services.remote is None
            else None
        )
        sleeper = asyncio.create_task(_upkeep(services, settings.sleep_check_s))
        warmer = asyncio.create_task(views.warm_up(scene_memory))  # the graph page's first list
        freezer = asyncio.create_task(_freeze_once_loaded(scene_memory))
        try:
            yield
        finally:
            sleeper.cancel()
            warmer.cancel()
            freezer.cancel()
            gc.unfreeze()  # what closed with this app must be collectable again (the store's lock)
            if withdraw is not None:
                withdraw()
            await run_in_threadpool(services.close)
            app.state.services = None

    app = FastAPI(
        title="Engram",
        summary="A human-like memory for robots, kept as a knowledge graph",
        version="0.2.0",
        lifespan=lifespan,
        telemetry=fastapi_telemetry(settings),  # OpenTelemetry, decided once (api/telemetry.py)
    )
    app.state.settings = settings
    install_error_handlers(app)
    armor.install(app)  # the ARMOR services, ahead of the other routes (api/routes/armor.py)
    for module in (health, sparql, export, admin, episodes, streams, ask, history):
        app.include_router(module.router)
    views.install(app)  # the web views: JSON under /views, pages under /web (api/web/)
    install_error_docs(app)  # the 401/404/409/422 answers in /openapi.json (api/openapi_errors.py)
    # hosts, cross-site writes, body limits, NaN and Infinity in JSON bodies (api/security.py)
    security.install(app, settings)
    return app
