"""What a store holds, as rich tables for the command line."""

from rich.console import Console
from rich.table import Table

from kg import OntologyStatus, Store
from kg.store import Binding
from ontologies.vocab import (
    DEFAULT_POLICY,
    EPISODES,
    EPISODIC,
    GRAPH_NS,
    MEMORY,
    OWL_NS,
    TBOX,
    TRASH,
)

__all__ = ["MEMORY_GRAPHS", "memory_sizes", "print_summary", "reset_memories"]

MEMORY_GRAPHS = (MEMORY, EPISODIC, TRASH, EPISODES)
"""The graphs a robot's life fills; the T-Box and the ARMOR references are not among them."""


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


def reset_memories(store: Store) -> None:
    """Empty the memory graphs in one transaction (the T-Box and references stay)."""
    with store.transaction() as tx:
        for graph in MEMORY_GRAPHS:
            tx.clear_graph(graph)
