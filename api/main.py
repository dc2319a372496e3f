"""The FastAPI application over one on-disk store."""

import asyncio
import datetime as dt
import gc
import logging
import time
from collections.abc import AsyncIterator
from contextlib import asynccontextmanager

from fastapi import FastAPI
from starlette.concurrency import run_in_threadpool

from api import fast_armor, security
from api.armor import ArmorEngine
from api.armor.memory import sleep_if_due
from api.backend import open_archive, open_store
from api.config import Settings, get_settings
from api.errors import install_error_handlers
from api.finite_json import FiniteJsonBodies
from api.memory_state import live_memory_state
from api.openapi_errors import install_error_docs
from api.routes import admin, armor, ask, episodes, export, health, history, sparql, streams, views
from episodes import EpisodeMemory
from episodes.streams import RecordingRegistry
from kg import ensure_ontology
from reasoners.clock import SettableClock
from reasoners.memory import SceneMemory

__all__ = ["create_app"]

log = logging.getLogger(__name__)


async def _sleep_when_due(memory: SceneMemory, period_s: float) -> None:
    """Check every ``period_s`` whether the policy's sleep interval has passed, and sleep then;
    then write the score view the updates since the last read left, and flush what the store
    committed since the last check.

    Updates also trigger the pass (every N of them); this covers a memory left alone. The flush
    writes the store's in-memory tables to its files, so that opening it after a crash replays
    only what came after (committed writes are safe either way, in the write-ahead log).
    """
    store = memory.store
    flushed = store.generation
    saved_at = time.monotonic()
    while True:
        await asyncio.sleep(period_s)
        if not memory.ready:  # still opening in the background
            continue
        await run_in_threadpool(sleep_if_due, memory)
        # the score view of the updates since the last read, so that the files converge
        await run_in_threadpool(_settle_view, memory)
        if store.generation != flushed:
            flushed = store.generation
            await run_in_threadpool(store.flush)
        if time.monotonic() - saved_at >= INDEX_SAVE_INTERVAL_S:
            saved_at = time.monotonic()
            await run_in_threadpool(_save_index, memory)


INDEX_SAVE_INTERVAL_S = 300.0
"""How often the scene memory's index file is brought up to date (if the memory changed), so
that a restart after a crash reads a recent one; a clean shutdown saves it too."""


def _save_index(memory: SceneMemory) -> None:
    """Save the memory's index file; a failure costs the next start a rebuild, nothing else."""
    try:
        memory.save_index()
    except Exception:
        log.exception("the scene memory's index file could not be saved")


def _settle_view(memory: SceneMemory) -> None:
    """Write the score view's pending changes; a failure is the next reader's to report."""
    try:
        memory.settle_view()
    except Exception:
        log.exception("the scene memory's score view could not be written")


async def _freeze_once_loaded(memory: SceneMemory, poll_s: float = 0.5) -> None:
    """Once the scene memory has loaded, hand the process's heap so far (the memory model
    above all: millions of objects at 100,000 classes) to the collector's permanent generation
    (``gc.freeze``), so that its full collections stop walking it. Unfrozen at shutdown.

    At 100,000 classes a full collection during an update walks the whole model: the slowest
    reinforce of 80 took 392 ms with it and 70 ms without (median 57 against 52 ms)."""
    while not memory.wait_ready(timeout_s=0):
        await asyncio.sleep(poll_s)
    gc.freeze()


def _utc_now() -> dt.datetime:
    return dt.datetime.now(dt.UTC)


def create_app(settings: Settings | None = None) -> FastAPI:
    """Build the app; the store opens when it starts and closes when it stops."""
    settings = settings or get_settings()

    @asynccontextmanager
    async def lifespan(app: FastAPI) -> AsyncIterator[None]:
        opened = open_store(settings)  # embedded, or a memory on a SPARQL server (issue 19)
        store = opened.store
        status = ensure_ontology(store)
        log.info("store %s: ontology %s %s", opened.where, status.version.value, status.action)
        runner = opened.runner(settings)
        recordings = RecordingRegistry()
        state = app.state
        state.settings, state.store, state.runner = settings, store, runner
        state.ontology_version = status.version  # the TBOX changes only here while serving
        state.recordings = recordings
        # Opened in the background (reading its index file, or rebuilding it from the store):
        # /health and SPARQL answer meanwhile, memory directives answer "loading".
        clock = SettableClock() if settings.clock_settable else _utc_now
        # `engram serve` refuses a damaged store before this (reasoners.check)
        state.scene_memory = scene_memory = SceneMemory(store, clock=clock, background=True)
        opened.watch(scene_memory)
        state.armor = ArmorEngine(
            store,
            scene_memory=scene_memory,
            sandbox=runner,
            max_list_length=settings.armor_max_list_length,
            files=security.armor_file_access(settings),  # confined (api/armor/files.py)
        )
        state.episodes = EpisodeMemory(
            store,
            data_dir=settings.data_dir,
            recordings=recordings,
            memory_state=live_memory_state(scene_memory),
            archive=open_archive(settings),
        )
        sleeper = asyncio.create_task(_sleep_when_due(scene_memory, settings.sleep_check_s))
        warmer = asyncio.create_task(views.warm_up(scene_memory))  # the graph page's first list
        freezer = asyncio.create_task(_freeze_once_loaded(scene_memory))
        try:
            yield
        finally:
            sleeper.cancel()
            warmer.cancel()
            freezer.cancel()
            gc.unfreeze()  # what closed with this app must be collectable again (the store's lock)
            recordings.close_all()  # a recording still open at shutdown ends as a complete file
            runner.close()
            if scene_memory.wait_ready(timeout_s=0):
                await run_in_threadpool(_save_index, scene_memory)
            store.flush()
            opened.close()
            # release the store's directory lock
            state.store = state.runner = state.armor = state.episodes = state.scene_memory = None

    app = FastAPI(
        title="Engram",
        summary="A human-like memory for robots, kept as a knowledge graph",
        version="0.2.0",
        lifespan=lifespan,
    )
    install_error_handlers(app)
    # armor first: route matching is a sizeable share of a directive's time
    for module in (armor, health, sparql, export, admin, episodes, streams, ask, history):
        app.include_router(module.router)
    views.install(app)  # the web views: JSON under /views, pages under /web (api/web/)
    app.add_middleware(
        FiniteJsonBodies
    )  # NaN, Infinity, 1e999 in a JSON body: 422 (api/finite_json.py)
    install_error_docs(app)  # the 401/404/409/422 answers in /openapi.json (api/openapi_errors.py)
    fast_armor.install(app)  # well-formed ARMOR requests skip the router (api/fast_armor.py)
    security.install(app, settings)  # hosts, cross-site writes, body limits (api/security.py)
    return app
