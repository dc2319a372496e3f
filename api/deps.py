"""FastAPI dependencies: the services the app opened at start-up, the settings and the write
guard. Every service lives on ``app.state`` for the app's lifetime (see ``api/main.py``)."""

import secrets
from typing import Annotated

from fastapi import Depends, Header, HTTPException, Request, status

from api.armor import ArmorEngine
from api.config import Settings
from episodes import EpisodeMemory
from episodes.streams import RecordingRegistry
from kg import Store
from kg.sandbox import QueryRunner

__all__ = [
    "ArmorDep",
    "EpisodesDep",
    "RecordingsDep",
    "RunnerDep",
    "SettingsDep",
    "StoreDep",
    "require_token",
]


async def _settings(request: Request) -> Settings:
    settings: Settings = request.app.state.settings
    return settings


async def _store(request: Request) -> Store:
    store: Store = request.app.state.store
    return store


async def _runner(request: Request) -> QueryRunner:
    runner: QueryRunner = request.app.state.runner
    return runner


async def _armor(request: Request) -> ArmorEngine:
    engine: ArmorEngine = request.app.state.armor
    return engine


async def _episodes(request: Request) -> EpisodeMemory:
    memory: EpisodeMemory = request.app.state.episodes
    return memory


async def _recordings(request: Request) -> RecordingRegistry:
    registry: RecordingRegistry = request.app.state.recordings
    return registry


SettingsDep = Annotated[Settings, Depends(_settings)]
StoreDep = Annotated[Store, Depends(_store)]
RunnerDep = Annotated[QueryRunner, Depends(_runner)]
ArmorDep = Annotated[ArmorEngine, Depends(_armor)]
EpisodesDep = Annotated[EpisodeMemory, Depends(_episodes)]
RecordingsDep = Annotated[RecordingRegistry, Depends(_recordings)]


async def require_token(
    settings: SettingsDep, authorization: Annotated[str | None, Header()] = None
) -> None:
    """Let the request through if no token is configured or it carries the right bearer token."""
    if settings.token is None:
        return
    expected = settings.token.get_secret_value()
    scheme, _, given = (authorization or "").partition(" ")
    if scheme.lower() != "bearer" or not secrets.compare_digest(given.strip(), expected):
        raise HTTPException(
            status.HTTP_401_UNAUTHORIZED,
            "this endpoint writes and needs 'Authorization: Bearer <token>' (ENGRAM_TOKEN)",
            headers={"WWW-Authenticate": "Bearer"},
        )
