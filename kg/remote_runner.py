"""Answer analysts' SPARQL over a memory on a shared server, checked as the embedded runner does.

A :class:`RemoteQueryRunner` is a :class:`kg.sandbox.QueryRunner` over an empty local store: its
worker processes check every caller's text first (nesting depth, syntax, updates, ``SERVICE``,
as Oxigraph's parser reads them, never in the server process) by running it over no data; a
query that passes is then answered by the memory's SPARQL server over the memory's own graphs
(or the graphs the request names), and over the graphs of the other robots' memories it follows
(``fleet``: a callable listing their server graph names, which change as they learn). Queries
given their data (``graph_data``, ARMOR's view of a
reference inside a directive list) run in the workers as before. The time limit is the HTTP
request's; start the server with its own (``oxigraph serve --timeout-s``) so it stops too.

>>> RemoteQueryRunner.__name__
'RemoteQueryRunner'
"""

from collections.abc import Callable, Mapping
from pathlib import Path

import httpx
from pyoxigraph import NamedNode, QueryResultsFormat, QueryTriples, RdfFormat

from kg.errors import QueryTimeoutError, ResultTooLargeError, StoreError
from kg.remote import RemoteDataset
from kg.sandbox import RESULT_FORMATS, QueryAnswer, QueryForm, QueryRunner
from kg.store import Store

__all__ = ["RemoteQueryRunner"]


class RemoteQueryRunner(QueryRunner):
    """A :class:`~kg.sandbox.QueryRunner` whose checked queries the memory's server answers.

    ``check_dir`` holds the empty local store the workers check queries against.
    Raises :class:`StoreError` unless ``store`` is on a SPARQL server.
    """

    def __init__(
        self,
        store: Store,
        *,
        check_dir: Path,
        workers: int = 2,
        timeout_s: float = 10.0,
        max_result_bytes: int = 64 * 1024 * 1024,
        max_query_chars: int = 1024 * 1024,
        max_depth: int = 128,
        fleet: Callable[[], list[str]] = list,
    ) -> None:
        if store.remote is None:
            raise StoreError("a RemoteQueryRunner needs a store on a SPARQL server")
        self.dataset: RemoteDataset = store.remote
        self.remote_store = store
        self.fleet = fleet
        check_dir.mkdir(parents=True, exist_ok=True)
        super().__init__(
            Store(check_dir / "store"),
            snapshot_dir=check_dir / "snapshots",
            workers=workers,
            timeout_s=timeout_s,
            max_result_bytes=max_result_bytes,
            max_query_chars=max_query_chars,
            max_depth=max_depth,
        )

    def run(
        self,
        text: str,
        *,
        media_types: Mapping[QueryForm, str],
        default_graphs: list[str] | None = None,
        named_graphs: list[str] | None = None,
        graph_data: Mapping[str, bytes] | None = None,
        timeout_s: float | None = None,
    ) -> QueryAnswer:
        """As :meth:`QueryRunner.run`; without ``graph_data`` the server answers once a worker
        has checked the text (over no data)."""
        checked = super().run(
            text,
            media_types=media_types,
            default_graphs=default_graphs,
            named_graphs=named_graphs,
            graph_data=graph_data if graph_data is not None else {},
            timeout_s=timeout_s,
        )
        if graph_data is not None or checked.media_type is None:
            return checked
        name = RESULT_FORMATS[checked.form][checked.media_type]
        try:
            if default_graphs is None:
                result = self.dataset.query(
                    text, use_default_graph_as_union=True, also=self.fleet()
                )
            else:  # no named-graph-uri: GRAPH reaches every graph of the memory, as embedded
                named = (
                    [*self.dataset.named_graphs(), *map(NamedNode, self.fleet())]
                    if named_graphs is None
                    else [NamedNode(g) for g in named_graphs]
                )
                result = self.dataset.query(
                    text, default_graph=[NamedNode(g) for g in default_graphs], named_graphs=named
                )
        except StoreError as error:
            if isinstance(error.__cause__, httpx.TimeoutException):
                raise QueryTimeoutError(
                    f"the query ran longer than the time limit of {self.timeout_s:g} s; "
                    "narrow it, or add a LIMIT"
                ) from None
            raise
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
        return QueryAnswer(checked.form, checked.media_type, data)

    def snapshot_is_current(self) -> bool:
        """Always False: a caller with a reference's data sends it rather than snapshot."""
        return False
