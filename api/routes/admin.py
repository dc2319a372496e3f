"""Operator endpoints that write; each needs the bearer token when one is configured."""

import datetime as dt
from typing import Any

from fastapi import APIRouter, Depends, status
from starlette.concurrency import run_in_threadpool

from api.deps import SettingsDep, StoreDep, require_token

router = APIRouter(tags=["admin"], dependencies=[Depends(require_token)])


@router.post("/backup", status_code=status.HTTP_201_CREATED, summary="Back up the store")
async def backup(store: StoreDep, settings: SettingsDep) -> dict[str, Any]:
    """Write a consistent copy of the store under ``<data_dir>/backups/<UTC time>``; the answer
    names it relative to the data directory (``backups/<UTC time>``)."""
    stamp = dt.datetime.now(dt.UTC).strftime("%Y%m%dT%H%M%S.%fZ")
    await run_in_threadpool(store.backup, settings.backup_dir / stamp)
    return {"backup": f"{settings.backup_dir.name}/{stamp}"}
