"""A robot's graph names on a shared server: the renaming is exact and touches IRIs only."""

import pytest
from hypothesis import given
from hypothesis import strategies as st

from kg.namespace import Namespace
from ontologies.vocab import GRAPH_NS, MEMORY

NS = Namespace("robot-a")


@pytest.mark.parametrize(
    ("name", "fragment"),
    [
        ("", "expected 1-64 letters"),
        ("two words", "'two words'"),
        ("-leading", "starting with a letter or digit"),
        ("x" * 65, "1-64"),
        ("a/b", "'a/b'"),
    ],
)
def test_a_bad_memory_name_is_refused_with_the_value(name: str, fragment: str) -> None:
    with pytest.raises(ValueError, match="memory: got") as caught:
        Namespace(name)
    assert fragment in str(caught.value)


def test_graph_iris_are_renamed_in_iris_and_prefix_declarations_but_not_in_strings() -> None:
    text = (
        f"PREFIX g: <{GRAPH_NS}>\n"
        f'SELECT * {{ GRAPH <{MEMORY.value}> {{ ?s ?p "<{MEMORY.value}>" }} }} # <{MEMORY.value}>'
    )
    renamed = NS.rewrite_text(text)
    assert renamed.count(NS.graph_prefix) == 2
    assert f'"<{MEMORY.value}>"' in renamed and f"# <{MEMORY.value}>" in renamed
    assert NS.restore_text(renamed) == text


def test_other_memories_graphs_are_not_renamed_back() -> None:
    other = Namespace("robot-b").remote_iri(MEMORY.value)
    assert NS.local_iri(other) == other
    assert NS.local(NS.remote(MEMORY)) == MEMORY


PIECES = st.sampled_from([*"ab/<>\"' #\n{}", GRAPH_NS, "memory"])


@given(st.lists(PIECES, max_size=30).map("".join))
def test_renaming_and_restoring_any_text_gives_it_back(text: str) -> None:
    assert NS.restore_text(NS.rewrite_text(text)) == text


def test_results_xml_is_restored_in_uri_elements_only() -> None:
    remote = NS.remote_iri(MEMORY.value)
    data = f"<uri>{remote}</uri><literal>{remote}</literal>".encode()
    assert (
        NS.restore_results_xml(data)
        == f"<uri>{MEMORY.value}</uri><literal>{remote}</literal>".encode()
    )
