"""A query worker process: ``python -m kg._query_worker FD``.

It answers jobs from :mod:`kg.sandbox` over the socket ``FD``, one at a time, each a read-only
query against a snapshot directory, and is killed when a query runs past its time limit.
"""

import io
import sys
from multiprocessing.connection import Connection
from typing import Any

import pyoxigraph
from pyoxigraph import NamedNode, QueryResultsFormat, RdfFormat


class _LimitedSink(io.BytesIO):
    """A binary file in memory that refuses to grow past ``limit`` bytes."""

    def __init__(self, limit: int) -> None:
        super().__init__()
        self.limit = limit
        self.overflowed = False

    def write(self, data: Any) -> int:
        if self.tell() + len(data) > self.limit:
            self.overflowed = True
            raise OSError("result size limit reached")
        return super().write(data)


def _graphs(iris: tuple[str, ...] | None) -> list[NamedNode] | None:
    return [NamedNode(iri) for iri in iris] if iris is not None else None


def answer(store: pyoxigraph.Store, job: dict[str, Any]) -> tuple[str, Any]:
    """Run one job; return ("ok", bytes), ("too_large", None) or ("syntax", message)."""
    try:
        result = store.query(
            job["text"],
            use_default_graph_as_union=job["default_graphs"] is None,
            default_graph=_graphs(job["default_graphs"]),  # type: ignore[arg-type]
            named_graphs=_graphs(job["named_graphs"]),  # type: ignore[arg-type]
        )
    except SyntaxError as error:
        return ("syntax", f"not a valid SPARQL query: {error}")
    sink = _LimitedSink(job["limit"])
    formats: Any = RdfFormat if job["graph_form"] else QueryResultsFormat
    try:
        result.serialize(sink, getattr(formats, job["format"]))
    except OSError:
        if sink.overflowed:
            return ("too_large", None)
        raise
    return ("ok", sink.getvalue())


def serve(connection: Connection) -> None:
    """Answer jobs until the connection closes; keep the last snapshot open between jobs."""
    opened: tuple[str, pyoxigraph.Store] | None = None
    while True:
        try:
            job = connection.recv()
        except (EOFError, OSError):
            return
        try:
            if opened is None or opened[0] != job["path"]:
                opened = None  # close the old snapshot before opening the new one
                opened = (job["path"], pyoxigraph.Store.read_only(job["path"]))
            connection.send(answer(opened[1], job))
        except Exception as error:  # a worker must answer, whatever happened
            connection.send(("error", f"{type(error).__name__}: {error}"))


if __name__ == "__main__":
    serve(Connection(int(sys.argv[1])))
