"""What Engram needs to know about a SPARQL server's engine: where its endpoints are, and
whether it can hold an Engram transaction.

An engine qualifies when one SPARQL update request is atomic (a failing later operation keeps
nothing of the earlier ones) and readers never see half of it. Oxigraph does; Jena Fuseki (TDB2)
and Amazon Neptune document it; Virtuoso 7.2 open source keeps the first operation of a failing
request and is therefore refused. None of them detects write-write conflicts, which is why a
memory has one writer (:mod:`kg.lease`).

>>> PROFILES["oxigraph"].endpoints("http://127.0.0.1:7878/")
('http://127.0.0.1:7878/query', 'http://127.0.0.1:7878/update', 'http://127.0.0.1:7878/store')
"""

from dataclasses import dataclass

__all__ = ["PROFILES", "EngineProfile", "profile_named"]


@dataclass(frozen=True)
class EngineProfile:
    """An engine's endpoint paths (relative to the URL given) and what it can do."""

    name: str
    query_path: str
    update_path: str
    store_path: str
    atomic_updates: bool = True

    def endpoints(self, url: str) -> tuple[str, str, str]:
        """The query, update and Graph Store Protocol URLs of a server at ``url``."""
        base = url.rstrip("/")
        return (base + self.query_path, base + self.update_path, base + self.store_path)


PROFILES = {
    profile.name: profile
    for profile in (
        EngineProfile("oxigraph", "/query", "/update", "/store"),
        # ENGRAM_STORE_URL names the dataset: http://host:3030/engram
        EngineProfile("fuseki", "/query", "/update", "/data"),
        EngineProfile("virtuoso", "/sparql", "/sparql", "/sparql-graph-crud", atomic_updates=False),
    )
}


def profile_named(name: str) -> EngineProfile:
    """The profile called ``name``.

    Raises ``ValueError`` naming the known profiles for an unknown one, and for an engine that
    cannot hold a transaction.
    """
    profile = PROFILES.get(name)
    if profile is None:
        raise ValueError(f"store profile: got {name!r}, expected one of {', '.join(PROFILES)}")
    if not profile.atomic_updates:
        raise ValueError(
            f"store profile: {name} keeps the first operations of a failing update request, so it "
            "cannot hold an Engram transaction; use oxigraph or fuseki"
        )
    return profile
