"""Keyword search and VALUES binding in SPARQL text: the cached scans answer as a fresh scan,
for repeated texts, for texts too long to cache, and for texts without a ``WHERE {``."""

import re

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from pyoxigraph import Literal, NamedNode

from kg import sparql_text
from kg.sparql_text import CACHED_TEXT_LIMIT, bind_values, mentions_keyword

_FRAGMENTS = [
    "SELECT",
    "?s",
    "?service",
    "$where",
    "ex:where",
    "WHERE",
    "where",
    "{",
    "}",
    " ",
    "\n",
    "SERVICE",
    "service",
    "<http://x/SERVICE>",
    "<http://x/a>",
    '"WHERE {"',
    "'SERVICE'",
    '"""a " SERVICE\n"""',
    "# WHERE { SERVICE\n",
    "#",
    '"',
    "'",
    "<",
    ">",
]
_texts = st.lists(st.sampled_from(_FRAGMENTS), max_size=24).map("".join)


def _fresh_mentions(text: str, keyword: str) -> bool:
    """The uncached scan, written out as it was before the caches."""
    pattern = re.compile(rf"(?<![\w?$:]){re.escape(keyword)}\b", re.IGNORECASE)
    return bool(pattern.search(sparql_text._code_only(text)))


def _fresh_bind(text: str, bindings: dict[str, NamedNode | Literal]) -> str:
    match = sparql_text._WHERE.search(sparql_text._code_only(text))
    if match is None:
        raise ValueError("no WHERE")
    names = " ".join(f"?{name}" for name in bindings)
    values = " ".join(str(term) for term in bindings.values())
    return f"{text[: match.end()]} VALUES ({names}) {{ ({values}) }}{text[match.end() :]}"


BINDINGS: dict[str, NamedNode | Literal] = {"p": NamedNode("http://x/p"), "o": Literal('a "b"')}


@settings(max_examples=300, deadline=None)
@given(text=_texts, keyword=st.sampled_from(["SERVICE", "where", "select"]))
def test_cached_scans_answer_as_a_fresh_scan(text: str, keyword: str) -> None:
    for _ in range(2):  # the second call is answered by the caches
        assert mentions_keyword(text, keyword) == _fresh_mentions(text, keyword)
        try:
            expected = _fresh_bind(text, BINDINGS)
        except ValueError:
            with pytest.raises(ValueError, match="no 'WHERE \\{' group"):
                bind_values(text, BINDINGS)
        else:
            assert bind_values(text, BINDINGS) == expected


def test_texts_longer_than_the_limit_are_scanned_and_not_kept() -> None:
    padding = "# " + "x" * CACHED_TEXT_LIMIT + "\n"
    text = padding + "SELECT * WHERE { SERVICE <http://x/> { ?s ?p ?o } }"
    hidden = padding + "SELECT * WHERE { ?s ?p 'SERVICE' }"
    before = sparql_text._cached_code_only.cache_info().currsize
    assert mentions_keyword(text, "SERVICE") is True
    assert mentions_keyword(hidden, "SERVICE") is False
    assert bind_values(hidden, BINDINGS) == _fresh_bind(hidden, BINDINGS)
    with pytest.raises(ValueError, match="WHERE"):
        bind_values(padding + "SELECT * { ?s ?p ?o }", BINDINGS)
    assert sparql_text._cached_code_only.cache_info().currsize == before


def test_a_text_without_where_keeps_failing_after_it_is_cached() -> None:
    text = "SELECT * { ?s ?p 'WHERE {' } # WHERE {"
    for _ in range(3):
        with pytest.raises(ValueError, match="no 'WHERE \\{' group"):
            bind_values(text, BINDINGS)
    assert bind_values(text, {}) == text  # nothing to bind: the text as it is


def test_the_caches_are_bounded() -> None:
    for cache in (
        sparql_text._cached_code_only,
        sparql_text._cached_mentions,
        sparql_text._cached_where_end,
    ):
        for i in range(cache.cache_info().maxsize + 10):  # type: ignore[operator]
            mentions_keyword(f"SELECT * WHERE {{ ?s ?p {i} }}", "SERVICE")
            bind_values(f"SELECT * WHERE {{ ?s ?p {i} }}", BINDINGS)
        info = cache.cache_info()
        assert info.maxsize is not None and info.currsize <= info.maxsize


@pytest.mark.parametrize("line_end", ["\r", "\n", "\r\n"])
def test_a_comment_ends_at_a_carriage_return_too(line_end: str) -> None:
    text = f"SELECT * WHERE {{ # x{line_end}SERVICE <http://x/> {{ ?s ?p ?o }} }}"
    assert mentions_keyword(text, "SERVICE")


def test_nesting_depth_ignores_brackets_in_strings_and_comments() -> None:
    from kg.sparql_text import nesting_depth

    assert nesting_depth("ASK { { ?s ?p '{{{{' } } # ((((\r FILTER((1)) ") == 2


def test_disable_keyword_changes_every_spelling() -> None:
    from kg.sparql_text import disable_keyword

    text = "sErViCe SERVIC\\u0045 servic\\U00000065 <http://x/service> 'service' ?service"
    assert "service" not in disable_keyword(text, "service").lower().replace("\\u0045", "e")
