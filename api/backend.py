"""Which store the server opens: the embedded one in ``data_dir`` (the default), or a memory on
a shared SPARQL server (``ENGRAM_STORE_URL``) as its writer or, with ``ENGRAM_FOLLOW``, as a
follower that keeps its scene memory in step with the writer's journal."""

import logging
from dataclasses import dataclass

from api.config import Settings
from episodes.archive import StreamArchive
from episodes.streams.objects import ObjectStore
from kg import Store
from kg.fleet import RemoteMemory, open_remote
from kg.remote import Change
from kg.remote_runner import RemoteQueryRunner
from kg.sandbox import QueryRunner
from ontologies.vocab import ENGRAM_NS
from reasoners.follow import apply_change
from reasoners.memory import SceneMemory

__all__ = ["OpenedStore", "open_archive", "open_store"]

log = logging.getLogger(__name__)


@dataclass
class OpenedStore:
    """The store the app serves, and the remote memory behind it if there is one."""

    store: Store
    where: str
    remote: RemoteMemory | None = None

    def runner(self, settings: Settings) -> QueryRunner:
        """The analysts' SPARQL runner: worker processes over snapshots, or the server."""
        if self.remote is not None:
            return RemoteQueryRunner(
                self.store,
                check_dir=settings.snapshot_dir,
                workers=settings.sparql_workers,
                timeout_s=settings.sparql_timeout_s,
                max_result_bytes=settings.sparql_max_result_bytes,
                max_query_chars=settings.sparql_max_query_bytes,
                max_depth=settings.sparql_max_nesting,
                fleet=self.remote.fleet_graphs,
            )
        return QueryRunner(
            self.store,
            snapshot_dir=settings.snapshot_dir,
            workers=settings.sparql_workers,
            timeout_s=settings.sparql_timeout_s,
            max_result_bytes=settings.sparql_max_result_bytes,
            max_query_chars=settings.sparql_max_query_bytes,
            max_depth=settings.sparql_max_nesting,
            snapshot_max_age_s=settings.sparql_snapshot_max_age_s,
        )

    def watch(self, memory: SceneMemory) -> None:
        """Bring ``memory``'s index up to date when the store changes behind it: the classes a
        change the follower read from the journal names, or everything after a failed write."""
        if self.remote is None:
            return

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
        if self.remote is not None:
            self.remote.close()


def open_store(settings: Settings) -> OpenedStore:
    """Open the store ``settings`` name (see the module's summary)."""
    if settings.store_url is None:
        if settings.fleet_memories:
            raise ValueError("fleet: following other memories needs store_url")
        return OpenedStore(Store(settings.store_dir), str(settings.store_dir))
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
    return OpenedStore(
        remote.store, f"memory {settings.memory} at {settings.store_url} ({role}{fleet})", remote
    )


def open_archive(settings: Settings) -> StreamArchive | None:
    """Object storage for ended episodes' recordings (``ENGRAM_STREAMS_URL``), if set; the
    credentials come from the usual AWS variables or files."""
    if settings.streams_url is None:
        return None
    objects = ObjectStore(settings.streams_url, endpoint_url=settings.streams_endpoint)
    return StreamArchive(
        objects, settings.data_dir / "streams", cache_bytes=settings.streams_cache_bytes
    )
