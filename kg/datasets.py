"""The dataset an analyst's SPARQL query reads by default: the live memory, not the trash.

A query sent to ``/sparql`` without ``default-graph-uri`` reads as its default graph the union
of every named graph except ``trash`` (forgotten classes and experienced scenes) and ``history``
(the scene memory's events, reasoners.history): the T-Box, the learned classes (``memory``), the
experienced scenes (``episodic``), the episodes and every ARMOR reference with its inferences.
Trash and history stay reachable by name, ``GRAPH <…/graph/trash>``, as does every other graph;
a ``default-graph-uri`` in the request chooses the default graph itself.

>>> from pyoxigraph import Literal
>>> from kg.store import Store
>>> from ontologies.vocab import MEMORY, RDFS_LABEL, TRASH, engram
>>> store = Store()
>>> with store.transaction() as tx:
...     tx.insert(engram("Scene-1"), RDFS_LABEL, Literal("live"), MEMORY)
...     tx.insert(engram("Scene-2"), RDFS_LABEL, Literal("forgotten"), TRASH)
>>> [g.rsplit("/", 1)[-1] for g in analyst_default_graphs(store)]
['memory']
"""

from kg.store import Store
from ontologies.vocab import HISTORY, TRASH

__all__ = ["NOT_IN_DEFAULT", "analyst_default_graphs"]

NOT_IN_DEFAULT = frozenset({TRASH, HISTORY})
"""Graphs an analyst reaches only by name."""


def analyst_default_graphs(store: Store) -> list[str]:
    """The IRIs of the graphs whose union is an analyst's default graph, sorted."""
    return sorted(g.value for g in store.named_graphs() if g not in NOT_IN_DEFAULT)
