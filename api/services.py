"""The composition root: the one place that opens a memory and builds the services over it.

Every entry point (the HTTP server, each command of the CLI, the demo, the local transport of
the Python client, the ROS node, the tests) calls :func:`open_services` with its
:class:`~api.config.Settings` and gets a :class:`Services`. So every entry point honours the
same settings: the data directory, a memory on a shared SPARQL server (``store_url``, as its
writer or, with ``follow``, as a follower that keeps its scene memory in step with the writer's
journal), object storage for recordings (``streams_url``).

The store opens at once; the scene memory, the episodes, the directive engine, the SPARQL
runner and the recordings registry are built on first use, so a command that needs only the
episodes never loads the scene memory's index, and only the server starts query workers.

A running server announces itself in ``<data dir>/server.json`` (its URL), so that a command
that finds the store held by it can name the server to talk to instead (:class:`StoreBusyError`).
"""

import json
import logging
import os
import time
from collections.abc import Callable
from functools import cached_property
from pathlib import Path
from typing import TYPE_CHECKING

from api.config import Settings
from kg import Store, ensure_ontology
from kg.clock import Clock, utc_now
from kg.errors import NotFoundError, StoreLockedError
from ontologies.vocab import ENGRAM_NS

if TYPE_CHECKING:
    from api.armor import ArmorEngine
    from episodes import EpisodeMemory
    from episodes.archive import StreamArchive
    from episodes.streams import RecordingRegistry
    from kg.fleet import RemoteMemory
    from kg.ontology import OntologyStatus
    from kg.sandbox import QueryRunner
    from reasoners.memory import SceneMemory

__all__ = [
    "MemoryNotFoundError",
    "Services",
    "StoreBusyError",
    "announce_server",
    "open_services",
    "running_server",
]

log = logging.getLogger(__name__)


SERVER_FILE = "server.json"
"""Written by a running server in its data directory: ``{"url": ..., "pid": ...}``."""


class MemoryNotFoundError(NotFoundError):
    """The data directory holds no memory, and the command does not create one."""


class StoreBusyError(StoreLockedError):
    """The store is held by another process; ``server`` is the URL of the Engram server that
    announced itself in the data directory, if any."""

    def __init__(self, message: str, server: str | None) -> None:
        super().__init__(message)
        self.server = server


INDEX_SAVE_INTERVAL_S = 300.0
"""How often a serving process brings the scene memory's index file up to date (if the memory
changed), so that a restart after a crash reads a recent one; closing saves it too."""


def _logged(action: Callable[[], object], failure: str) -> None:
    try:
        action()
    except Exception:
        log.exception(failure)


class Services:
    """One memory and the services over it; close it (or use it as a context manager) to
    release the store."""

    def __init__(
        self,
        settings: Settings,
        store: Store,
        where: str,
        *,
        remote: "RemoteMemory | None" = None,
        clock: Clock | None = None,
        background: bool = False,
        serving: bool = False,
    ) -> None:
        self.settings = settings
        self.store = store
        self.where = where
        """Where the memory is, in words: a directory, or a memory on a SPARQL server."""
        self.remote = remote
        self.clock: Clock = clock or utc_now
        self._background = background
        self._serving = serving
        self.ontology: OntologyStatus = ensure_ontology(store)
        """The T-Box version in the store and what opening did to it."""
        self._flushed = store.generation
        self._index_saved_at = time.monotonic()

    @cached_property
    def scene_memory(self) -> "SceneMemory":
        """The scene memory; with ``background`` it loads in a thread (``ready`` tells)."""
        from reasoners.memory import SceneMemory

        memory = SceneMemory(self.store, clock=self.clock, background=self._background)
        self._watch(memory)
        return memory

    @cached_property
    def recordings(self) -> "RecordingRegistry":
        from episodes.streams import RecordingRegistry

        return RecordingRegistry()

    @cached_property
    def archive(self) -> "StreamArchive | None":
        """Object storage for ended episodes' recordings (``streams_url``), if set; the
        credentials come from the usual AWS variables or files."""
        settings = self.settings
        if settings.streams_url is None:
            return None
        from episodes.archive import StreamArchive
        from episodes.streams.objects import ObjectStore

        objects = ObjectStore(settings.streams_url, endpoint_url=settings.streams_endpoint)
        return StreamArchive(
            objects,
            settings.data_dir / "streams",
            cache_bytes=settings.streams_cache_bytes,
            read_limit_bytes=settings.mcap_read_limit_bytes,
        )

    @cached_property
    def episodes(self) -> "EpisodeMemory":
        """The autobiographical memory; its snapshots rank classes by the live scene memory."""
        from episodes import EpisodeMemory
        from episodes.model import MemorySnapshot

        def live_state(store: Store) -> MemorySnapshot:
            from api.memory_state import live_memory_state

            return live_memory_state(self.scene_memory)(store)

        return EpisodeMemory(
            self.store,
            data_dir=self.settings.data_dir,
            clock=self.clock,
            recordings=self.recordings,
            memory_state=live_state,
            archive=self.archive,
            read_limit_bytes=self.settings.mcap_read_limit_bytes,
        )

    @cached_property
    def runner(self) -> "QueryRunner":
        """The analysts' SPARQL runner: worker processes over snapshots, or the server."""
        settings = self.settings
        limits = {
            "workers": settings.sparql_workers,
            "timeout_s": settings.sparql_timeout_s,
            "max_result_bytes": settings.sparql_max_result_bytes,
            "max_query_chars": settings.sparql_max_query_bytes,
            "max_depth": settings.sparql_max_nesting,
        }
        if self.remote is not None:
            from kg.remote_runner import RemoteQueryRunner

            return RemoteQueryRunner(
                self.store,
                check_dir=settings.snapshot_dir,
                fleet=self.remote.fleet_graphs,
                **limits,  # type: ignore[arg-type]
            )
        from kg.sandbox import QueryRunner

        return QueryRunner(
            self.store,
            snapshot_dir=settings.snapshot_dir,
            snapshot_max_age_s=settings.sparql_snapshot_max_age_s,
            **limits,  # type: ignore[arg-type]
        )

    @cached_property
    def armor(self) -> "ArmorEngine":
        """The ARMOR directive engine over the scene memory; in a serving process QUERY SPARQL
        runs in the runner's sandboxed workers, elsewhere in this process. Its file commands
        reach only the data directory and the directories and URLs the settings allow."""
        from api.armor import ArmorEngine
        from api.security import armor_file_access

        return ArmorEngine(
            self.store,
            scene_memory=self.scene_memory,
            sandbox=self.runner if self._serving else None,
            max_list_length=self.settings.armor_max_list_length,
            files=armor_file_access(self.settings),  # confined (api/armor/files.py)
        )

    def upkeep(self) -> None:
        """What a serving process does every ``sleep_check_s``: the sleep pass when the policy's
        interval has passed (updates also trigger it, every N of them; this covers a memory left
        alone), the score view the updates since the last read left (so that the store's files
        converge on a memory nobody reads), a flush of what the store committed since the last
        upkeep (so that opening it after a crash replays only what came after; committed writes
        are safe either way, in the write-ahead log), and every ``INDEX_SAVE_INTERVAL_S`` the
        scene memory's index file. A failing step is logged and tried again next time."""
        memory = self.scene_memory
        if not memory.loaded.ready:  # still opening in the background
            return
        from api.armor.memory import sleep_if_due

        sleep_if_due(memory)
        _logged(
            memory.transactions.settle_view, "the scene memory's score view could not be written"
        )
        if self.store.generation != self._flushed:
            self._flushed = self.store.generation
            _logged(self.store.flush, "the store could not be flushed")
        if time.monotonic() - self._index_saved_at >= INDEX_SAVE_INTERVAL_S:
            self._index_saved_at = time.monotonic()
            _logged(memory.save_index, "the scene memory's index file could not be saved")

    def _watch(self, memory: "SceneMemory") -> None:
        """Bring ``memory``'s index up to date when the store changes behind it: the classes a
        change the follower read from the journal names, or everything after a failed write."""
        if self.remote is None:
            return
        from kg.remote import Change
        from reasoners.follow import apply_change

        def changed(change: Change) -> None:
            if change.touched is not None and not any(
                iri.value.startswith(ENGRAM_NS) for iri in change.touched
            ):
                return  # nothing of the scene memory (episodes, references)
            piecewise = apply_change(memory, change.touched)
            log.info(
                "scene memory at revision %d (%s)",
                change.revision,
                "the changed classes reloaded" if piecewise else "rebuilt",
            )

        self.remote.dataset.listen(changed)

    def close(self) -> None:
        """End what was built (recordings still open end as complete files, query workers
        stop), save the scene memory's index, flush and release the store."""
        built = self.__dict__
        if "recordings" in built:
            self.recordings.close_all()
        if "episodes" in built:
            self.episodes.close()
        if "runner" in built:
            self.runner.close()
        memory = built.get("scene_memory")
        if memory is not None and memory.loaded.wait_ready(timeout_s=0):
            # a failure costs the next start a rebuild, nothing else
            _logged(memory.save_index, "the scene memory's index file could not be saved")
        if self.remote is not None:
            self.store.flush()
            self.remote.close()
        else:
            self.store.close()  # the directory is free for another process from here on

    def __enter__(self) -> "Services":
        return self

    def __exit__(self, *_: object) -> None:
        self.close()


def open_services(
    settings: Settings,
    *,
    create: bool = False,
    clock: Clock | None = None,
    background: bool = False,
    serving: bool = False,
) -> Services:
    """Open the memory ``settings`` name: the embedded store in ``settings.data_dir``, or a
    memory on the SPARQL server at ``settings.store_url``.

    An embedded memory that does not exist yet is created only with ``create`` (the demo, a
    server started with ``--init``); otherwise :class:`MemoryNotFoundError`. ``background`` opens
    the scene memory in a thread; ``serving`` (the server, the ROS node) runs QUERY SPARQL in
    the sandboxed query workers. A store held by
    another process raises :class:`StoreBusyError`, naming the server that announced itself in
    the data directory."""
    if settings.store_url is None:
        if settings.fleet_memories:
            raise ValueError("fleet: following other memories needs store_url")
        if not create and not settings.store_dir.is_dir():
            raise MemoryNotFoundError(
                f"no memory in {settings.data_dir} (no store/ there); `engram demo` or "
                "`engram serve --init` creates one, or name another with --data or "
                "ENGRAM_DATA_DIR"
            )
        try:
            store = Store(settings.store_dir)
        except StoreLockedError as error:
            server = running_server(settings.data_dir)
            hint = f"; the Engram server at {server} holds it" if server else ""
            raise StoreBusyError(f"{error}{hint}", server) from None
        return Services(
            settings,
            store,
            str(settings.data_dir),
            clock=clock,
            background=background,
            serving=serving,
        )
    from kg.fleet import open_remote

    remote = open_remote(
        settings.store_url,
        settings.memory,
        profile=settings.store_profile,
        follow=settings.follow,
        lease_s=settings.lease_s,
        fleet=settings.fleet_memories,
    )
    role = "following" if settings.follow else "writing"
    fleet = f", following {settings.fleet}" if settings.fleet_memories else ""
    where = f"memory {settings.memory} at {settings.store_url} ({role}{fleet})"
    return Services(
        settings,
        remote.store,
        where,
        remote=remote,
        clock=clock,
        background=background,
        serving=serving,
    )


def announce_server(data_dir: Path, url: str) -> Callable[[], None]:
    """Write ``server.json`` in ``data_dir`` naming ``url``; return the function that removes
    it (the server calls it when it stops)."""
    path = data_dir / SERVER_FILE
    partial = path.with_name(SERVER_FILE + ".part")
    partial.write_text(json.dumps({"url": url, "pid": os.getpid()}))
    partial.replace(path)

    def withdraw() -> None:
        path.unlink(missing_ok=True)

    return withdraw


def running_server(data_dir: Path) -> str | None:
    """The URL of the Engram server serving ``data_dir``, if one announced itself there and its
    process is alive."""
    try:
        announced = json.loads((data_dir / SERVER_FILE).read_text())
        url, pid = str(announced["url"]), int(announced["pid"])
    except (OSError, ValueError, KeyError, TypeError):
        return None
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return None
    except PermissionError:
        pass  # alive, another user's
    return url
