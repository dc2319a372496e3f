"""Engram's settings, read from ``ENGRAM_*`` environment variables and validated.

>>> Settings(sparql_timeout_s=2.5).sparql_timeout_s
2.5
"""

import os
from functools import lru_cache
from pathlib import Path
from typing import Literal

from pydantic import Field, SecretStr
from pydantic_settings import BaseSettings, SettingsConfigDict

__all__ = ["Settings", "default_data_dir", "get_settings", "machine_memory_bytes"]


def machine_memory_bytes() -> int:
    """This machine's physical memory, in bytes (1 GiB if the system does not say)."""
    try:
        return os.sysconf("SC_PHYS_PAGES") * os.sysconf("SC_PAGE_SIZE")
    except (ValueError, OSError, AttributeError):
        return 1024**3


def _share_of_memory(fraction: float, *, floor_bytes: int, cap_bytes: int) -> int:
    """``fraction`` of the machine's memory, kept between ``floor_bytes`` and ``cap_bytes``."""
    return max(floor_bytes, min(cap_bytes, int(machine_memory_bytes() * fraction)))


def default_data_dir() -> Path:
    """``$XDG_DATA_HOME/engram``, or ``~/.local/share/engram``."""
    base = os.environ.get("XDG_DATA_HOME") or Path.home() / ".local" / "share"
    return Path(base) / "engram"


class Settings(BaseSettings):
    """Everything an operator can set, with its unit in its name."""

    model_config = SettingsConfigDict(env_prefix="ENGRAM_", extra="ignore", frozen=True)

    data_dir: Path = Field(
        default_factory=default_data_dir,
        description="Directory of the store, its query snapshots and backups.",
    )
    host: str = Field("127.0.0.1", min_length=1, description="Address the server listens on.")
    port: int = Field(8000, ge=1, le=65535, description="TCP port the server listens on.")
    token: SecretStr | None = Field(
        None, description="If set, every write endpoint requires 'Authorization: Bearer <token>'."
    )
    sparql_timeout_s: float = Field(
        10.0, gt=0, le=3600, description="Time limit of one SPARQL query, in seconds."
    )
    sparql_max_result_bytes: int = Field(
        64 * 1024 * 1024, gt=0, description="Largest serialised SPARQL result, in bytes."
    )
    sparql_max_query_bytes: int = Field(
        1024 * 1024,
        gt=0,
        description="Longest SPARQL request body (and query text), in bytes; longer answers 413.",
    )
    sparql_max_nesting: int = Field(
        128,
        ge=1,
        le=1000,
        description="Deepest nesting of braces, parentheses and brackets in a SPARQL query.",
    )
    sparql_snapshot_max_age_s: float = Field(
        0.0,
        ge=0,
        le=60,
        description="A SPARQL query may read a snapshot up to this old while writers commit "
        "(0: every query sees every commit made before it).",
    )
    sparql_workers: int = Field(
        2, ge=1, le=64, description="Worker processes that answer SPARQL queries in parallel."
    )

    armor_max_list_length: int = Field(
        100_000,
        ge=1,
        description="Most directives one ARMOR directive list may hold; longer answers 422.",
    )

    sleep_check_s: float = Field(
        30.0,
        gt=0,
        le=86400,
        description="How often the server checks whether the memory's sleep pass is due, in s.",
    )

    clock_settable: bool = Field(
        False,
        description="Let the MEMORY CLOCK SET / ADVANCE directives set the scene memory's clock "
        "(simulated days for tests and demos); never on a robot's real memory.",
    )
    store_url: str | None = Field(
        None,
        pattern=r"^https?://\S+$",
        description="A SPARQL server holding the memory (unset: the embedded store in data_dir).",
    )
    store_profile: Literal["oxigraph", "fuseki"] = Field(
        "oxigraph", description="The engine at store_url: where its endpoints are."
    )
    memory: str = Field(
        "default",
        pattern=r"^[A-Za-z0-9][A-Za-z0-9_-]{0,63}$",
        description="This robot's memory (its graph namespace) on the SPARQL server.",
    )
    follow: bool = Field(
        False, description="Open the memory on the server read-only and follow its writer."
    )
    lease_s: float = Field(
        15.0, gt=0, le=3600, description="Term of the writer's lease on the server, in seconds."
    )
    fleet: str = Field(
        "",
        pattern=r"^([A-Za-z0-9][A-Za-z0-9_-]{0,63}(,[A-Za-z0-9][A-Za-z0-9_-]{0,63})*)?$",
        description="Other robots' memories on the SPARQL server to follow read-only, comma "
        "separated: /sparql then also sees each under its server graph names "
        "(https://w3id.org/engram/memory/<name>/graph/<g>). Needs store_url.",
    )

    streams_url: str | None = Field(
        None,
        pattern=r"^s3://[a-z0-9][a-z0-9.-]{1,61}[a-z0-9](/\S*)?$",
        description="s3://bucket/prefix where ended episodes' recordings go (unset: kept local).",
    )
    streams_endpoint: str | None = Field(
        None,
        pattern=r"^https?://\S+$",
        description="URL of the S3-compatible service of streams_url (unset: AWS's own).",
    )
    mcap_read_limit_bytes: int = Field(
        1024**3,
        gt=0,
        description="Most bytes one MCAP record, or one chunk once decompressed, may take when "
        "a recording is read (replay, export, runs, views); a file declaring more is refused "
        "as damaged (409). Bounds the memory a decompression bomb can take.",
    )
    streams_cache_bytes: int = Field(
        10 * 1024**3,
        ge=0,
        description="Most bytes of recordings fetched back from streams_url (for export) kept "
        "in data_dir/streams; the least recently used go first. Replay reads by ranges and "
        "fetches nothing; recordings made here are never evicted.",
    )

    allowed_hosts: str = Field(
        "",
        pattern=r"^[^\s]*$",
        description="Host names the server answers to (the Host header), comma separated; "
        "'*' for any. Unset: localhost, 127.0.0.1, ::1, the listening address and this "
        "machine's host name (with .local). Any other Host answers 400 (DNS rebinding).",
    )
    allowed_origins: str = Field(
        "",
        pattern=r"^[^\s]*$",
        description="Other web origins (scheme://host[:port]) whose pages may write, comma "
        "separated. A write whose Origin (or Sec-Fetch-Site) says it comes from any other "
        "site answers 403, with or without a token.",
    )
    max_body_bytes: int = Field(
        default_factory=lambda: _share_of_memory(
            1 / 64, floor_bytes=16 * 1024**2, cap_bytes=256 * 1024**2
        ),
        gt=0,
        description="Longest request body, in bytes, except bag uploads; longer answers 413. "
        "Default: 1/64 of the machine's memory, between 16 and 256 MiB.",
    )
    max_upload_bytes: int = Field(
        4 * 1024**3,
        gt=0,
        description="Longest bag upload (POST /episodes/import/upload), in bytes, streamed to "
        "data_dir/uploads; longer answers 413.",
    )
    max_decompressed_bytes: int = Field(
        default_factory=lambda: _share_of_memory(
            1 / 32, floor_bytes=64 * 1024**2, cap_bytes=512 * 1024**2
        ),
        gt=0,
        description="Most bytes one compressed piece of an imported file (a bag chunk or "
        "message) may expand to, and most bytes a tar upload may unpack to (times 8); more "
        "answers 422. Default: 1/32 of the machine's memory, between 64 and 512 MiB.",
    )
    body_timeout_s: float = Field(
        30.0,
        gt=0,
        le=3600,
        description="Longest wait for the next part of a request body, in seconds; a client "
        "that stops sending answers 408. Needs the server's protocol from api/header_timeout.py "
        "(engram serve uses it).",
    )
    header_timeout_s: float = Field(
        10.0,
        gt=0,
        le=3600,
        description="Longest wait for a request's headers, from the connection or the "
        "request's first byte, in seconds; a connection that takes longer is closed (408). "
        "Needs the server's protocol from api/header_timeout.py (engram serve uses it).",
    )
    telemetry: Literal["auto", "on", "off"] = Field(
        "auto",
        description="FastAPI's OpenTelemetry spans, metrics and logs: 'on', 'off', or 'auto' "
        "(on if the OpenTelemetry SDK is installed or a provider is configured when the server "
        "starts). Decided once, when the app is built (api/telemetry.py).",
    )
    armor_file_dirs: str = Field(
        "",
        description="Directories, besides data_dir, that ARMOR's LOAD FILE, SAVE and LOG FILE "
        "may read and write, separated by the path separator (':').",
    )
    armor_url_prefixes: str = Field(
        "",
        pattern=r"^[^\s]*$",
        description="URL prefixes ARMOR's LOAD WEB may fetch, comma separated (unset: none; "
        "LOAD WEB is refused).",
    )

    @property
    def fleet_memories(self) -> list[str]:
        return [name for name in self.fleet.split(",") if name]

    @property
    def store_dir(self) -> Path:
        return self.data_dir / "store"

    @property
    def snapshot_dir(self) -> Path:
        return self.data_dir / "snapshots"

    @property
    def backup_dir(self) -> Path:
        return self.data_dir / "backups"


@lru_cache
def get_settings() -> Settings:
    """The process's settings, read once; tests override the dependency instead."""
    return Settings()
