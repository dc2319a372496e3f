"""Restoring a store from a backup (a directory written by :meth:`kg.Store.backup`, as
``engram backup`` and ``POST /backup`` make them).

The backup is copied (never linked: the restored store writes its own files) beside the store,
opened to check that it is an Engram store, then swapped in with two renames. The store it
replaces is kept, moved to ``keep``, so a restore can itself be undone. A server holding the
store makes the restore refuse: its lock is tried before the copy and again just before the
swap (the store is closed between, so that closing it cannot write into the restored one).
"""

import datetime as dt
import gc
import logging
import shutil
from pathlib import Path

from kg.errors import InvalidInputError, NotFoundError, StoreError
from kg.store import Store
from ontologies.vocab import TBOX

__all__ = ["restore_backup"]

log = logging.getLogger(__name__)


def _check_backup(backup: Path, store_dir: Path) -> None:
    if not backup.is_dir():
        raise NotFoundError(f"backup: {backup} is not a directory")
    if not (backup / "CURRENT").is_file():
        raise InvalidInputError(
            f"backup: {backup} holds no store (no CURRENT file); expected a directory "
            "written by `engram backup` or POST /backup"
        )
    if backup.resolve() == store_dir.resolve():
        raise InvalidInputError(f"backup: {backup} is the store itself")


def _check_unlocked(store_dir: Path) -> None:
    """Raise :class:`StoreLockedError` if another process holds the store at ``store_dir``."""
    if (store_dir / "CURRENT").is_file():
        held = Store(store_dir)
        del held
        gc.collect()


def _open_copy(copy: Path, backup: Path) -> None:
    """Open the copy once: it must be a store holding the Engram T-Box."""
    try:
        store = Store(copy)
        held = store.graph_sizes()
    except StoreError as error:
        raise InvalidInputError(f"backup: {backup} does not open as a store: {error}") from None
    del store
    gc.collect()  # release the copy's lock before it is renamed into place
    if TBOX.value not in held:
        raise InvalidInputError(f"backup: {backup} is a store without the Engram T-Box")


def restore_backup(backup: Path, store_dir: Path, *, keep: Path | None = None) -> Path | None:
    """Make a copy of ``backup`` the store at ``store_dir``; returns where the store it replaced
    was moved (``keep``, by default ``backups/before-restore-<UTC time>`` beside the store), or
    ``None`` if there was none.

    Raises :class:`NotFoundError` if ``backup`` is not a directory, :class:`InvalidInputError`
    if it does not hold an Engram store, :class:`StoreLockedError` if another process (a
    server) has the store open, and ``FileExistsError`` if ``keep`` exists. Nothing is changed
    when it raises.
    """
    backup, store_dir = Path(backup), Path(store_dir)
    _check_backup(backup, store_dir)
    if keep is None:
        stamp = dt.datetime.now(dt.UTC).strftime("%Y%m%dT%H%M%S.%fZ")
        keep = store_dir.parent / "backups" / f"before-restore-{stamp}"
    if keep.exists():
        raise FileExistsError(f"keep: {keep} already exists")
    _check_unlocked(store_dir)
    staging = store_dir.with_name(store_dir.name + ".restoring")
    if staging.exists():  # left by a restore that was interrupted
        shutil.rmtree(staging)
    try:
        shutil.copytree(backup, staging)
        _open_copy(staging, backup)
        _check_unlocked(store_dir)
        kept = store_dir.exists() and any(store_dir.iterdir())
        if kept:
            keep.parent.mkdir(parents=True, exist_ok=True)
            store_dir.rename(keep)
        elif store_dir.exists():
            store_dir.rmdir()
        staging.rename(store_dir)
    finally:
        if staging.exists():
            shutil.rmtree(staging)
    log.info("restored %s from %s (the previous store kept at %s)", store_dir, backup, keep)
    return keep if kept else None
