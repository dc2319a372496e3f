"""Small, careful operations on SPARQL text: finding keywords outside strings, IRIs and comments,
and binding terms as a ``VALUES`` row.

>>> bind_values("SELECT ?s WHERE { ?s ?p ?o }", {"p": NamedNode("http://x/p")})
'SELECT ?s WHERE { VALUES (?p) { (<http://x/p>) } ?s ?p ?o }'

Scanning a text costs tens of microseconds, and the stored queries are run again and again, so
the scans of texts up to ``CACHED_TEXT_LIMIT`` characters are kept in bounded LRU caches (the
stored queries are a small fixed set; the callers' queries vary, and are bounded in number and
size so that the caches stay small).
"""

import functools
import re
from collections.abc import Mapping, Sequence

from pyoxigraph import Literal, NamedNode

__all__ = ["bind_table", "bind_values", "mentions_keyword"]

_NOT_CODE = re.compile(
    r'"""(?:[^"\\]|\\.|"(?!""))*"""'
    r"|'''(?:[^'\\]|\\.|'(?!''))*'''"
    r'|"(?:[^"\\\n]|\\.)*"'
    r"|'(?:[^'\\\n]|\\.)*'"
    r"|<[^<>\"{}|^`\\\s]*>"
    r"|#[^\n]*",
)
_WHERE = re.compile(r"(?<![\w?$:])WHERE\s*\{", re.IGNORECASE)


CACHED_TEXT_LIMIT = 16_384
"""Texts longer than this are scanned on every call rather than kept in the caches."""
_CACHED_TEXTS = 256


def _code_only(text: str) -> str:
    """``text`` with strings, IRIs and comments blanked out, offsets unchanged."""
    return _NOT_CODE.sub(lambda match: " " * len(match.group()), text)


_cached_code_only = functools.lru_cache(maxsize=_CACHED_TEXTS)(_code_only)


def _code(text: str) -> str:
    return _cached_code_only(text) if len(text) <= CACHED_TEXT_LIMIT else _code_only(text)


@functools.lru_cache(maxsize=64)
def _keyword_pattern(keyword: str) -> re.Pattern[str]:
    return re.compile(rf"(?<![\w?$:]){re.escape(keyword)}\b", re.IGNORECASE)


def _mentions(text: str, keyword: str) -> bool:
    return bool(_keyword_pattern(keyword).search(_code(text)))


_cached_mentions = functools.lru_cache(maxsize=_CACHED_TEXTS)(_mentions)


def mentions_keyword(text: str, keyword: str) -> bool:
    """True if ``keyword`` appears as a keyword, not in a string, IRI, name or comment.

    >>> mentions_keyword("SELECT * { SERVICE <http://x/> { ?s ?p ?o } }", "service")
    True
    >>> mentions_keyword("SELECT * { ?s ?p 'SERVICE' } # SERVICE", "SERVICE")
    False
    """
    if len(text) <= CACHED_TEXT_LIMIT:
        return _cached_mentions(text, keyword)
    return _mentions(text, keyword)


def _where_end(text: str) -> int | None:
    """The offset just after the first ``WHERE {`` outside strings, IRIs and comments."""
    match = _WHERE.search(_code(text))
    return None if match is None else match.end()


_cached_where_end = functools.lru_cache(maxsize=_CACHED_TEXTS)(_where_end)


def bind_values(text: str, bindings: Mapping[str, NamedNode | Literal]) -> str:
    """Bind variables by opening the first ``WHERE {`` group with a one-row ``VALUES`` block.

    This is what SEP-0007 substitution means for a group, and unlike pyoxigraph's
    ``substitutions`` (which filters after the fact) the query planner uses the bound terms to
    start its joins. Terms are written by pyoxigraph's own serialisation, which escapes them;
    nothing else of the caller's reaches the text. Raises ``ValueError`` if the query has no
    ``WHERE {`` and ``TypeError`` for a term that cannot be written in ``VALUES``.
    """
    if not bindings:
        return text
    return bind_table(text, list(bindings), [list(bindings.values())])


def bind_table(
    text: str, names: Sequence[str], rows: Sequence[Sequence[NamedNode | Literal]]
) -> str:
    """Like :func:`bind_values`, with several rows: the query answers for each row.

    >>> bind_table("SELECT ?s WHERE { ?s ?p ?o }", ["s"], [[NamedNode("http://x/a")], [NamedNode("http://x/b")]])
    'SELECT ?s WHERE { VALUES (?s) { (<http://x/a>) (<http://x/b>) } ?s ?p ?o }'
    """
    for name in names:
        if not name.isidentifier():
            raise ValueError(f"binding name: got {name!r}, expected a SPARQL variable name")
    for row in rows:
        if len(row) != len(names):
            raise ValueError(f"binding row: got {len(row)} terms, expected {len(names)}")
        for name, term in zip(names, row, strict=True):
            if not isinstance(term, NamedNode | Literal):
                raise TypeError(f"binding {name}: got {term!r}, expected a NamedNode or a Literal")
    end = _cached_where_end(text) if len(text) <= CACHED_TEXT_LIMIT else _where_end(text)
    if end is None:
        raise ValueError("the query has no 'WHERE {' group to bind variables in")
    header = " ".join(f"?{name}" for name in names)
    body = " ".join("(" + " ".join(str(term) for term in row) + ")" for row in rows)
    return f"{text[:end]} VALUES ({header}) {{ {body} }}{text[end:]}"
