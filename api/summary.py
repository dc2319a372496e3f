"""What a store holds, as rich tables for the command line, and emptying it of a memory."""

import logging
import shutil
from pathlib import Path

from pyoxigraph import NamedNode
from rich.console import Console
from rich.table import Table

from kg import OntologyStatus, Store
from kg.store import Binding
from ontologies.vocab import (
    DEFAULT_POLICY,
    EPISODES,
    EPISODIC,
    GRAPH_NS,
    HISTORY,
    MEMORY,
    OWL_NS,
    TBOX,
    TRASH,
)
from reasoners.index_file import index_path

__all__ = ["MEMORY_FILES", "MEMORY_GRAPHS", "memory_sizes", "print_summary", "reset_memories"]

log = logging.getLogger(__name__)

MEMORY_GRAPHS = (MEMORY, EPISODIC, TRASH, EPISODES, HISTORY)
"""The graphs a robot's life fills; the T-Box and the ARMOR references are not among them."""

MEMORY_FILES = ("streams", "augmentations", "uploads")
"""The data directory's folders of a memory's files: the episodes' recordings, the augmentation
runs' derived samples, uploads in progress (``episodes.paths.DataPaths``)."""


def _text(term: Binding) -> str:
    return str(getattr(term, "value", term))


def print_summary(console: Console, store: Store, status: OntologyStatus | None = None) -> None:
    """Print the ontology version, the size of every graph, the T-Box entities and the policy."""
    where = str(store.path) if store.path else "memory"
    if status is not None:
        console.print(
            f"[bold]Engram store[/bold] at {where}: ontology {status.version.value} "
            f"({status.action})"
        )
    graphs = Table(title="Named graphs", title_justify="left")
    graphs.add_column("graph")
    graphs.add_column("triples", justify="right")
    for iri, size in store.graph_sizes().items():
        graphs.add_row(iri.removeprefix(GRAPH_NS), str(size))
    console.print(graphs)

    entities = Table(title="T-Box entities", title_justify="left")
    entities.add_column("kind")
    entities.add_column("count", justify="right")
    for row in store.select("entity_counts", graph=TBOX):
        entities.add_row(_text(row["kind"]).removeprefix(OWL_NS), _text(row["count"]))
    console.print(entities)

    policy = Table(title="Memory policy (engram:defaultPolicy)", title_justify="left")
    policy.add_column("setting")
    policy.add_column("value", justify="right")
    for row in store.select("policy_values", graph=TBOX, policy=DEFAULT_POLICY):
        policy.add_row(_text(row["label"]), _text(row["value"]))
    console.print(policy)


def memory_sizes(store: Store) -> dict[str, int]:
    """Triples in each memory graph, by short name."""
    sizes = store.graph_sizes()
    return {g.value.removeprefix(GRAPH_NS): sizes.get(g.value, 0) for g in MEMORY_GRAPHS}


def reset_memories(store: Store, data_dir: Path | None = None) -> list[Path]:
    """Empty every graph but the T-Box in one transaction, then delete the memory's files under
    ``data_dir`` (by default the directory holding an on-disk store named ``store``, as a data
    directory lays it out; no files otherwise): what is left is the store of a fresh data
    directory. Returns the folders and files deleted.

    The graphs cleared are the memory's (:data:`MEMORY_GRAPHS`), its history and revision, and
    the ARMOR references; the files are :data:`MEMORY_FILES` and the scene memory's index file
    beside the store. Backups (``backups/``) are kept.
    """
    graphs = [NamedNode(iri) for iri in store.graph_sizes() if iri != TBOX.value]
    with store.transaction() as tx:
        for graph in {*graphs, *MEMORY_GRAPHS}:
            tx.clear_graph(graph)
    if data_dir is None and store.path is not None and store.path.name == "store":
        data_dir = store.path.parent  # the data directory's layout (Settings.store_dir)
    deleted: list[Path] = []
    if data_dir is not None:
        for name in MEMORY_FILES:
            if (data_dir / name).is_dir():
                shutil.rmtree(data_dir / name)
                deleted.append(data_dir / name)
    index = index_path(store)
    if index is not None and index.exists():
        index.unlink()
        deleted.append(index)
    log.info("reset: cleared %d graphs, deleted %s", len(graphs), deleted)
    return deleted
