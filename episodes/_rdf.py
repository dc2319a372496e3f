"""Small helpers to read the terms that query rows hold."""

import datetime as dt

from pyoxigraph import Literal, NamedNode

from episodes.times import from_literal

Row = dict[str, NamedNode | Literal]


def text(row: Row, name: str) -> str:
    return row[name].value


def opt_text(row: Row, name: str) -> str | None:
    return row[name].value if name in row else None


def integer(row: Row, name: str) -> int:
    return int(row[name].value)


def number(row: Row, name: str) -> float:
    return float(row[name].value)


def opt_number(row: Row, name: str) -> float | None:
    return float(row[name].value) if name in row else None


def time(row: Row, name: str) -> dt.datetime:
    return from_literal(row[name])


def opt_time(row: Row, name: str) -> dt.datetime | None:
    return from_literal(row[name]) if name in row else None


def iri(row: Row, name: str) -> NamedNode:
    term = row[name]
    if not isinstance(term, NamedNode):
        raise TypeError(f"{name}: expected an IRI, got {term!r}")
    return term


def names(row: Row, name: str = "participants") -> tuple[str, ...]:
    """The labels a query joined with U+001F (GROUP_CONCAT), sorted."""
    joined = row[name].value if name in row else ""
    return tuple(sorted(part for part in joined.split("\x1f") if part))
