"""A query worker process: ``python -m kg._query_worker FD``.

It answers jobs from :mod:`kg.sandbox` over the socket ``FD``, one at a time, and is killed
when a job runs past its time limit. Everything a caller's query text goes through happens
here, never in the server: the nesting check, parsing, the refusal of ``SERVICE`` and updates,
evaluation and serialisation. A query that crashes the parser kills only this process.

Before the first job the process forbids itself Internet sockets (:mod:`kg._no_network`), so a
query that escaped the checks still cannot make the server fetch anything.

A job is a dict: ``text``; the data, either ``path`` (this worker's own copy of the store, a
backup directory it opens read-write) with ``replay`` (the commits to apply to it first, in
order: (inserted quads, or None and a SPARQL update text)) and optionally ``retire`` (its
previous copy, to close and remove), or ``graph_data`` (named graph IRI -> N-Triples bytes,
loaded into memory); ``default_graphs`` and
``named_graphs`` (IRIs, or None); ``formats`` (query form -> result format name, for the forms
the caller accepts); ``limit`` (bytes of result); ``max_depth`` (nesting levels). The answer is
a tuple ``(status, form, payload)``, ``status`` being one of ``ok`` (payload: the result),
``not_acceptable``, ``too_large``, ``too_deep``, ``syntax``, ``refused``, ``unsupported``,
``replay_failed`` (the copy could not be brought up to date: the server sends a new one) or
``error`` (payload: a message).
"""

import io
import logging
import shutil
import signal
import sys
from multiprocessing.connection import Connection
from typing import Any

import pyoxigraph
from pyoxigraph import NamedNode, QueryBoolean, QueryResultsFormat, QuerySolutions, RdfFormat

from kg._no_network import forbid_network
from kg.sparql_text import disable_keyword, nesting_depth

log = logging.getLogger(__name__)

Answer = tuple[str, str | None, Any]

_guarded = False
"""True once this process cannot open Internet sockets."""


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


def _form(result: object) -> str:
    if isinstance(result, QuerySolutions):
        return "solutions"
    if isinstance(result, QueryBoolean):
        return "boolean"
    return "graph"


def _evaluate(store: pyoxigraph.Store, text: str, job: dict[str, Any]) -> Any:
    return store.query(
        text,
        use_default_graph_as_union=job["default_graphs"] is None,
        default_graph=_graphs(job["default_graphs"]),  # type: ignore[arg-type]
        named_graphs=_graphs(job["named_graphs"]),  # type: ignore[arg-type]
    )


def check(text: str, job: dict[str, Any]) -> Answer | None:
    """Refuse ``text`` if it is too deep, does not parse as a query, or calls ``SERVICE``.

    pyoxigraph parses only to evaluate, so the parse runs over an empty store; an update does
    not parse as a query. ``SERVICE`` is found by Oxigraph's parser itself: the text with every
    spelling of the word changed must parse too, or the word was a keyword. Returns None when
    the query may run.
    """
    depth = nesting_depth(text)
    if depth > job["max_depth"]:
        return (
            "too_deep",
            None,
            f"the query nests {depth} levels of braces, parentheses or brackets; "
            f"at most {job['max_depth']} are allowed",
        )
    empty = pyoxigraph.Store()
    try:
        _evaluate(empty, disable_keyword(text, "service"), job)
    except SyntaxError:
        if not _guarded:  # evaluating the text to tell which it is could reach the network
            return ("refused", None, "the query does not parse, or it calls SERVICE")
        try:
            _evaluate(empty, text, job)
        except SyntaxError as error:
            return ("syntax", None, f"not a valid SPARQL query: {error}")
        return (
            "refused",
            None,
            "SERVICE (federated query) is disabled on this endpoint: it would let a query "
            "make the server contact other hosts",
        )
    return None


def _open(job: dict[str, Any], opened: dict[str, pyoxigraph.Store]) -> pyoxigraph.Store:
    if job.get("graph_data") is not None:
        store = pyoxigraph.Store()
        for iri, data in job["graph_data"].items():
            store.load(data, format=RdfFormat.N_TRIPLES, to_graph=NamedNode(iri))
        return store
    path = job["path"]
    if path not in opened:
        opened.clear()  # close the old copy before opening the new one
        opened[path] = pyoxigraph.Store(path)
    retired = job.get("retire")
    if retired:
        shutil.rmtree(retired, ignore_errors=True)
    return opened[path]


class ReplayError(Exception):
    """The worker's copy of the store could not take the commits it was sent."""


def _replay(store: pyoxigraph.Store, job: dict[str, Any]) -> None:
    try:
        for inserts, update in job.get("replay") or ():
            if inserts:
                store.extend(inserts)
            if update:
                store.update(update)
    except (OSError, SyntaxError, ValueError) as error:
        raise ReplayError(str(error)) from error


def answer(store: pyoxigraph.Store, job: dict[str, Any]) -> Answer:
    """Run one checked job over ``store`` and serialise its result."""
    text = job["text"]
    try:
        result = _evaluate(store, text, job)
    except SyntaxError as error:
        return ("syntax", None, f"not a valid SPARQL query: {error}")
    form = _form(result)
    format_name = job["formats"].get(form)
    if format_name is None:
        return ("not_acceptable", form, None)
    sink = _LimitedSink(job["limit"])
    formats: Any = RdfFormat if form == "graph" else QueryResultsFormat
    try:
        result.serialize(sink, getattr(formats, format_name))
    except OSError:
        if sink.overflowed:
            return ("too_large", form, None)
        raise
    return ("ok", form, sink.getvalue())


def handle(job: dict[str, Any], opened: dict[str, pyoxigraph.Store]) -> Answer:
    """Check, then run, one job; errors become answers."""
    try:
        store = _open(job, opened)
        if job.get("graph_data") is None:
            _replay(store, job)  # also for a refused query: the server counts it done
        refusal = check(job["text"], job)
        if refusal is not None:
            return refusal
        return answer(store, job)
    except ReplayError as error:
        opened.clear()
        return ("replay_failed", None, str(error))
    except RuntimeError as error:  # Oxigraph's word for an unknown function and the like
        return ("unsupported", None, f"the query cannot be evaluated: {error}")
    except ValueError as error:  # a malformed graph IRI
        return ("syntax", None, str(error))
    except Exception as error:  # a worker must answer, whatever happened
        return ("error", None, f"{type(error).__name__}: {error}")


def serve(connection: Connection) -> None:
    """Answer jobs until the connection closes; keep the last snapshot open between jobs."""
    opened: dict[str, pyoxigraph.Store] = {}
    while True:
        try:
            job = connection.recv()
        except (EOFError, OSError):
            return
        connection.send(handle(job, opened))


def main(fd: int) -> None:
    """Forbid the network, then serve the socket ``fd``. Ctrl-C at the server's terminal
    reaches its workers too: they ignore it and end when the server closes their socket."""
    global _guarded
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    try:
        forbid_network()
        _guarded = True
    except (OSError, NotImplementedError) as error:
        log.warning("query worker runs without its network guard: %s", error)
    serve(Connection(fd))


if __name__ == "__main__":
    main(int(sys.argv[1]))
