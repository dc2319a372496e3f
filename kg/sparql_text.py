"""Small, careful operations on SPARQL text: finding keywords outside strings, IRIs and comments,
and binding terms as a ``VALUES`` row.

>>> bind_values("SELECT ?s WHERE { ?s ?p ?o }", {"p": NamedNode("http://x/p")})
'SELECT ?s WHERE { VALUES (?p) { (<http://x/p>) } ?s ?p ?o }'
"""

import re
from collections.abc import Mapping

from pyoxigraph import Literal, NamedNode

__all__ = ["bind_values", "mentions_keyword"]

_NOT_CODE = re.compile(
    r'"""(?:[^"\\]|\\.|"(?!""))*"""'
    r"|'''(?:[^'\\]|\\.|'(?!''))*'''"
    r'|"(?:[^"\\\n]|\\.)*"'
    r"|'(?:[^'\\\n]|\\.)*'"
    r"|<[^<>\"{}|^`\\\s]*>"
    r"|#[^\n]*",
)
_WHERE = re.compile(r"(?<![\w?$:])WHERE\s*\{", re.IGNORECASE)


def _code_only(text: str) -> str:
    """``text`` with strings, IRIs and comments blanked out, offsets unchanged."""
    return _NOT_CODE.sub(lambda match: " " * len(match.group()), text)


def mentions_keyword(text: str, keyword: str) -> bool:
    """True if ``keyword`` appears as a keyword, not in a string, IRI, name or comment."""
    pattern = re.compile(rf"(?<![\w?$:]){re.escape(keyword)}\b", re.IGNORECASE)
    return bool(pattern.search(_code_only(text)))


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
    for name, term in bindings.items():
        if not name.isidentifier():
            raise ValueError(f"binding name: got {name!r}, expected a SPARQL variable name")
        if not isinstance(term, NamedNode | Literal):
            raise TypeError(f"binding {name}: got {term!r}, expected a NamedNode or a Literal")
    match = _WHERE.search(_code_only(text))
    if match is None:
        raise ValueError("the query has no 'WHERE {' group to bind variables in")
    names = " ".join(f"?{name}" for name in bindings)
    values = " ".join(str(term) for term in bindings.values())
    return f"{text[: match.end()]} VALUES ({names}) {{ ({values}) }}{text[match.end() :]}"
