"""Engram's SPARQL, one ``.rq`` file per query, loaded by name.

Values never reach a query by string splicing: callers bind them as terms, which
:func:`kg.sparql_text.bind_values` writes as a ``VALUES`` row at the start of the query's first
``WHERE {`` group, so every file holds plain variables where values go and says ``WHERE {``.

>>> "SELECT" in load("graph_sizes")
True
"""

from functools import cache
from importlib.resources import files

from sparql.cue import CUE_NAME, cue_query

__all__ = ["load", "names"]


def names() -> list[str]:
    """The names of all stored queries, sorted."""
    return sorted(
        entry.name.removesuffix(".rq")
        for entry in files(__name__).iterdir()
        if entry.name.endswith(".rq")
    )


@cache
def load(name: str) -> str:
    """The text of the query stored as ``<name>.rq``, or of a cue query built from its
    template (:mod:`sparql.cue`).

    Raises ``KeyError`` naming the known queries when there is no such file.
    """
    resource = files(__name__).joinpath(f"{name}.rq")
    if not resource.is_file() and (cue := CUE_NAME.fullmatch(name)):
        return cue_query(cue[1], int(cue[2]))
    if not resource.is_file():
        raise KeyError(f"no SPARQL query named {name!r}; known: {', '.join(names())}")
    return resource.read_text(encoding="utf-8")
