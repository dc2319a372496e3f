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

__all__ = ["bind_table", "bind_values", "disable_keyword", "mentions_keyword", "nesting_depth"]

_NOT_CODE = re.compile(
    r'"""(?:[^"\\]|\\.|"(?!""))*"""'
    r"|'''(?:[^'\\]|\\.|'(?!''))*'''"
    r'|"(?:[^"\\\n\r]|\\.)*"'
    r"|'(?:[^'\\\n\r]|\\.)*'"
    r"|<[^<>\"{}|^`\\\s]*>"
    r"|#[^\n\r]*",  # SPARQL ends a comment at a line feed or a carriage return
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


def nesting_depth(text: str) -> int:
    """The deepest nesting of ``{``, ``(`` and ``[`` outside strings, IRIs and comments.

    Oxigraph's parser recurses once per level and overflows its stack past a few thousand, so
    the sandbox refuses deep texts before parsing them.

    >>> nesting_depth("SELECT * { { ?s ?p '{{{' } FILTER(1 = (2)) }")
    3
    """
    deepest = depth = 0
    for char in _code(text):
        if char in "{([":
            depth += 1
            deepest = max(deepest, depth)
        elif char in "})]" and depth:
            depth -= 1
    return deepest


def _spelled(letter: str) -> str:
    """A pattern for ``letter`` in either case, literally or as a ``\\u`` / ``\\U`` escape."""
    forms = [re.escape(letter.lower()), re.escape(letter.upper())]
    for code in {ord(letter.lower()), ord(letter.upper())}:
        forms += [rf"\\u{code:04x}", rf"\\U{code:08x}"]
    return "(?:" + "|".join(forms) + ")"


@functools.lru_cache(maxsize=16)
def _spelling_pattern(keyword: str) -> re.Pattern[str]:
    head = "".join(_spelled(c) for c in keyword[:-1])
    return re.compile(f"{head}({_spelled(keyword[-1])})", re.IGNORECASE)


def disable_keyword(text: str, keyword: str) -> str:
    """``text`` with every spelling of ``keyword`` (any case, escapes included) made another word.

    The last letter is replaced, wherever the word appears: in strings, IRIs, names and
    comments the text keeps its shape, while as a keyword it no longer parses. A parser that
    accepts ``text`` but not the result has read ``keyword`` as a keyword; that decision is the
    parser's own, not a scan's, so comments, escapes and line ends cannot hide the keyword.

    >>> disable_keyword("SELECT * { SERVICE <http://x/service> {} } # Service", "service")
    'SELECT * { SERVICQ <http://x/servicq> {} } # Servicq'
    """
    replacement = "q" if keyword[-1].lower() != "q" else "x"

    def swap(match: re.Match[str]) -> str:
        word, last = match.group(), match.group(1)
        letter = replacement.upper() if last.isupper() else replacement
        return word[: match.start(1) - match.start()] + letter

    return _spelling_pattern(keyword).sub(swap, text)


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
