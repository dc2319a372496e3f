"""Engram's SPARQL, one ``.rq`` file per query, loaded by name.

Values never reach a query by string splicing: callers bind them as terms (pyoxigraph
``substitutions``, SEP-0007), which is why the files hold plain variables where values go. A
variable a caller binds must appear in the query's projection (``SELECT ?graph ...``).

>>> "SELECT" in load("graph_sizes")
True
"""

from functools import cache
from importlib.resources import files

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
    """The text of the query stored as ``<name>.rq``.

    Raises ``KeyError`` naming the known queries when there is no such file.
    """
    resource = files(__name__).joinpath(f"{name}.rq")
    if not resource.is_file():
        raise KeyError(f"no SPARQL query named {name!r}; known: {', '.join(names())}")
    return resource.read_text(encoding="utf-8")
