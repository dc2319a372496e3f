"""FastAPI dependencies: the services the app opened at start-up (``app.state.services``, from
:func:`api.services.open_services`), the settings and the write guard."""

import secrets
from typing import Annotated

from fastapi import Depends, Header, HTTPException, Request, status

from api.armor import ArmorEngine
from api.config import Settings
from api.services import Services
from episodes import EpisodeMemory
from episodes.streams import RecordingRegistry
from kg import Store
from kg.sandbox import QueryRunner
from reasoners.memory import SceneMemory

__all__ = [
    "ArmorDep",
    "EpisodesDep",
    "RecordingsDep",
    "RunnerDep",
    "SceneMemoryDep",
    "ServicesDep",
    "SettingsDep",
    "StoreDep",
    "require_token",
]


async def _settings(request: Request) -> Settings:
    settings: Settings = request.app.state.settings
    return settings


async def _services(request: Request) -> Services:
    services: Services = request.app.state.services
    return services


async def _store(request: Request) -> Store:
    return (await _services(request)).store


async def _runner(request: Request) -> QueryRunner:
    return (await _services(request)).runner


async def _armor(request: Request) -> ArmorEngine:
    return (await _services(request)).armor


async def _episodes(request: Request) -> EpisodeMemory:
    return (await _services(request)).episodes


async def _recordings(request: Request) -> RecordingRegistry:
    return (await _services(request)).recordings


async def _scene_memory(request: Request) -> SceneMemory:
    return (await _services(request)).scene_memory


SettingsDep = Annotated[Settings, Depends(_settings)]
ServicesDep = Annotated[Services, Depends(_services)]
SceneMemoryDep = Annotated[SceneMemory, Depends(_scene_memory)]
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
