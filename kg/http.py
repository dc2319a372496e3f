"""Talking to a SPARQL 1.1 server: Query, Update and the Graph Store Protocol over httpx.

One keep-alive connection pool per server, a time limit on every request, and retries only where
they cannot repeat a write: a request is retried when the connection failed before anything was
sent, and a read (which changes nothing) also once after a dropped connection. Every transport
failure becomes :class:`kg.errors.StoreUnavailableError`; :attr:`SparqlServer.sent` says whether
the failed request may have reached the server.

Graph Store Protocol requests never use ``HEAD``: Oxigraph answers a ``HEAD`` on a missing graph
with a body, which breaks the pooled connection it came on.
"""

import logging
import time
from collections.abc import Sequence

import httpx

from kg.errors import QuerySyntaxError, StoreUnavailableError, TransactionError
from kg.profile import EngineProfile

__all__ = ["SparqlServer", "WriteOutcomeUnknownError"]

log = logging.getLogger(__name__)

_NOTHING_SENT = (httpx.ConnectError, httpx.ConnectTimeout, httpx.PoolTimeout)
_ATTEMPTS = 3
_RESULTS = "application/sparql-results+xml, application/n-triples;q=0.9"


class WriteOutcomeUnknownError(StoreUnavailableError):
    """The server went away after an update was sent: it may or may not have applied it."""


class SparqlServer:
    """The query, update and graph-store endpoints of one server, with a connection pool.

    ``timeout_s`` bounds each request (connecting takes at most ``connect_timeout_s``).
    """

    def __init__(
        self,
        url: str,
        profile: EngineProfile,
        *,
        timeout_s: float = 30.0,
        connect_timeout_s: float = 2.0,
    ) -> None:
        self.url = url
        self.query_url, self.update_url, self.store_url = profile.endpoints(url)
        self._client = httpx.Client(
            timeout=httpx.Timeout(timeout_s, connect=connect_timeout_s),
            limits=httpx.Limits(max_keepalive_connections=8, keepalive_expiry=30.0),
        )

    def close(self) -> None:
        self._client.close()

    def _send(self, request: httpx.Request, *, read_only: bool) -> httpx.Response:
        dropped = False
        for attempt in range(_ATTEMPTS):
            try:
                return self._client.send(request)
            except _NOTHING_SENT as error:
                failure: httpx.TransportError = error
            except httpx.TimeoutException as error:  # never repeated: it would take as long
                if not read_only:
                    raise WriteOutcomeUnknownError(
                        f"the SPARQL server at {self.url} did not answer a write in time; "
                        "whether it applied is checked against the memory's revision"
                    ) from error
                raise StoreUnavailableError(
                    f"the SPARQL server at {self.url} did not answer in time ({error!r})"
                ) from error
            except httpx.TransportError as error:
                if not read_only:
                    raise WriteOutcomeUnknownError(
                        f"the SPARQL server at {self.url} went away during a write ({error!r}); "
                        "whether it applied is checked against the memory's revision when the "
                        "server is back"
                    ) from error
                if dropped:
                    failure = error
                    break
                dropped = True  # a pooled connection the server had closed: once more
                continue
            if attempt + 1 < _ATTEMPTS:
                time.sleep(0.05 * 2**attempt)
        raise StoreUnavailableError(
            f"the SPARQL server at {self.url} cannot be reached ({failure!r}); nothing was "
            "written, retry when it is back"
        ) from failure

    def query(
        self, text: str, *, default_graphs: Sequence[str], named_graphs: Sequence[str]
    ) -> httpx.Response:
        """POST a query with an explicit dataset; the answer is SPARQL XML or N-Triples.

        Raises :class:`QuerySyntaxError` with the server's message when it refuses the text.
        """
        form = [("query", text)]
        form += [("default-graph-uri", g) for g in default_graphs]
        form += [("named-graph-uri", g) for g in named_graphs]
        request = self._client.build_request(
            "POST", self.query_url, data=dict(_grouped(form)), headers={"Accept": _RESULTS}
        )
        response = self._send(request, read_only=True)
        if response.status_code == 400:
            raise QuerySyntaxError(f"the SPARQL server refused the query: {response.text}")
        _raise_for_status(response, "query")
        return response

    def update(self, text: str) -> None:
        """POST one SPARQL update request (applied all or nothing by a qualifying engine).

        Raises :class:`TransactionError` when the server refuses it (nothing applied),
        :class:`WriteOutcomeUnknownError` when the connection broke after it was sent.
        """
        request = self._client.build_request(
            "POST",
            self.update_url,
            content=text.encode(),
            headers={"Content-Type": "application/sparql-update"},
        )
        response = self._send(request, read_only=False)
        if response.status_code >= 400:  # answered: a qualifying engine applied none of it
            raise TransactionError(
                f"the SPARQL server refused the update, nothing applied: "
                f"{response.status_code} {response.text[:500]}"
            )
        _raise_for_status(response, "update")

    def get_graph(self, graph: str) -> bytes | None:
        """The N-Triples of ``graph`` (Graph Store Protocol GET), or None if it does not exist."""
        request = self._client.build_request(
            "GET",
            self.store_url,
            params={"graph": graph},
            headers={"Accept": "application/n-triples"},
        )
        response = self._send(request, read_only=True)
        if response.status_code == 404:
            return None
        _raise_for_status(response, "graph read")
        return response.content

    def post_graph(self, graph: str, ntriples: bytes) -> None:
        """Add N-Triples to ``graph`` (Graph Store Protocol POST)."""
        request = self._client.build_request(
            "POST",
            self.store_url,
            params={"graph": graph},
            content=ntriples,
            headers={"Content-Type": "application/n-triples"},
        )
        response = self._send(request, read_only=False)
        if 400 <= response.status_code < 500:
            raise TransactionError(
                f"the SPARQL server refused the graph write, nothing applied: "
                f"{response.status_code} {response.text[:500]}"
            )
        _raise_for_status(response, "graph write")


def _grouped(pairs: list[tuple[str, str]]) -> dict[str, list[str]]:
    grouped: dict[str, list[str]] = {}
    for key, value in pairs:
        grouped.setdefault(key, []).append(value)
    return grouped


def _raise_for_status(response: httpx.Response, what: str) -> None:
    if response.status_code >= 300:
        raise StoreUnavailableError(
            f"the SPARQL server answered the {what} with {response.status_code}: "
            f"{response.text[:500]}"
        )
