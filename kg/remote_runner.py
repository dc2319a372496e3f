"""Answer analysts' SPARQL over a memory on a shared server, with the embedded runner's checks.

The query is checked exactly as :class:`kg.sandbox.QueryRunner` checks it (parsed, ``SERVICE``
refused), then run by the server over the memory's own graphs (or the graphs the request
names); the time limit is the HTTP request's, and the server should also be started with its
own (``oxigraph serve --timeout-s``) so that it stops the work too.

>>> RemoteQueryRunner.__name__
'RemoteQueryRunner'
"""

import httpx
import pyoxigraph
from pyoxigraph import NamedNode, QueryResultsFormat, QueryTriples, RdfFormat

from kg.errors import QueryTimeoutError, ResultTooLargeError, StoreError
from kg.remote import RemoteDataset
from kg.sandbox import RESULT_FORMATS, QueryRunner, QueryWork
from kg.store import Store

__all__ = ["RemoteQueryRunner"]


class RemoteQueryRunner(QueryRunner):
    """A :class:`~kg.sandbox.QueryRunner` whose queries the memory's SPARQL server answers."""

    def __init__(
        self, store: Store, *, timeout_s: float = 10.0, max_result_bytes: int = 64 * 1024 * 1024
    ) -> None:
        if store.remote is None:
            raise StoreError("a RemoteQueryRunner needs a store on a SPARQL server")
        # no worker processes and no snapshots: only what check() uses
        self.store = store
        self.dataset: RemoteDataset = store.remote
        self.timeout_s = timeout_s
        self.max_result_bytes = max_result_bytes
        self._checker = pyoxigraph.Store()

    def run(self, work: QueryWork, media_type: str) -> bytes:
        formats = RESULT_FORMATS[work.form]
        if media_type not in formats:
            raise ValueError(f"media_type: got {media_type!r}, expected one of {list(formats)}")
        try:
            if work.default_graphs is None:
                result = self.dataset.query(work.text, use_default_graph_as_union=True)
            else:
                result = self.dataset.query(
                    work.text,
                    default_graph=[NamedNode(g) for g in work.default_graphs],
                    named_graphs=[NamedNode(g) for g in work.named_graphs or ()],
                )
        except StoreError as error:
            if isinstance(error.__cause__, httpx.TimeoutException):
                raise QueryTimeoutError(
                    f"the query ran longer than the time limit of {self.timeout_s:g} s; "
                    "narrow it, or add a LIMIT"
                ) from None
            raise
        name = formats[media_type]
        if isinstance(result, QueryTriples):
            body = result.serialize(format=getattr(RdfFormat, name))
        else:
            body = result.serialize(format=getattr(QueryResultsFormat, name))
        data = bytes(body or b"")
        if len(data) > self.max_result_bytes:
            raise ResultTooLargeError(
                f"the result is larger than the limit of {self.max_result_bytes} bytes; "
                "add a LIMIT or select less"
            )
        return data

    def close(self) -> None:
        """Nothing to stop: the server runs the queries."""
