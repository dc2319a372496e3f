"""Cues by role (the paper's role='agent') and arguments given after the fact (issue 16 items
1 and 2)."""

from pathlib import Path

import pytest
from typer.testing import CliRunner

from api.cli import app as cli
from episodes import ArgumentSpec, Cue, EpisodeMemory, InvalidInputError, NotFoundError
from ontologies.vocab import EPISODES, PROV_INVALIDATED_AT_TIME, PROV_WAS_REVISION_OF
from tests.conftest import LiveServer

NOW = "2026-02-26T10:00:00+00:00"


@pytest.fixture
def two_pointings(memory: EpisodeMemory) -> EpisodeMemory:
    """HyungJin pointed once (p1); later Maxime pointed and HyungJin was the recipient (p2)."""
    memory.begin(
        "pointing",
        arguments=[ArgumentSpec("agent", "HyungJin"), ArgumentSpec("object", "ball")],
        begin="2026-01-26T15:30:00+00:00",
        episode_id="p1",
    )
    memory.begin(
        "pointing",
        arguments=[ArgumentSpec("agent", "Maxime"), ArgumentSpec("recipient", "HyungJin")],
        begin="2026-02-20T09:00:00+00:00",
        episode_id="p2",
    )
    return memory


def test_agent_means_the_agent_role(two_pointings: EpisodeMemory) -> None:
    m = two_pointings
    assert m.count(Cue("pointing", agent="HyungJin")) == 1
    assert m.recall(Cue("pointing", agent="HyungJin"), which="last").episode.id == "p1"
    assert [r.episode.id for r in m.all(Cue("pointing", agent="HyungJin"))] == ["p1"]
    assert m.recall(Cue("pointing", agent="HyungJin"), which="nth", n=1).episode.id == "p1"
    with pytest.raises(NotFoundError):
        m.recall(Cue("pointing", agent="HyungJin"), which="nth", n=2)


def test_role_and_participant_cover_the_other_cases(two_pointings: EpisodeMemory) -> None:
    m = two_pointings
    recipient = Cue("pointing", role="recipient", participant="HyungJin")
    assert [r.episode.id for r in m.all(recipient)] == ["p2"]
    assert m.count(Cue("pointing", participant="HyungJin")) == 2
    assert m.count(Cue("pointing", role="recipient")) == 1
    assert m.count(Cue("pointing", agent="Maxime", role="recipient", participant="HyungJin")) == 1
    assert m.count(Cue("pointing", obj="ball")) == 1
    found = m.recall(recipient, which="last")
    assert found.said == (
        "The last time HyungJin was the recipient of pointing was six days ago, on February 20th."
    )


def test_an_argument_added_after_the_fact_is_found_by_cue(memory: EpisodeMemory) -> None:
    memory.begin(
        "greeting",
        arguments=[ArgumentSpec("agent", "unknown")],
        begin="2026-02-25T10:00:00+00:00",
        episode_id="g1",
    )
    with pytest.raises(NotFoundError):
        memory.recall(Cue("greeting", agent="Martina"))
    added = memory.add_argument(
        "g1",
        role="agent",
        value="Martina",
        author="face recognition",
        confidence=0.92,
        replace=True,
    )
    assert (added.author, added.confidence) == ("face recognition", 0.92)
    assert memory.recall(Cue("greeting", agent="Martina")).episode.id == "g1"
    assert memory.count(Cue("greeting", agent="unknown")) == 0
    (argument,) = memory.get("g1").arguments
    assert (argument.value, argument.author, argument.confidence) == (
        "Martina",
        "face recognition",
        0.92,
    )
    assert argument.asserted is not None
    # the replaced assertion stays in the graph, invalidated and revised
    assert len(list(memory.store.quads(None, PROV_INVALIDATED_AT_TIME, None, EPISODES))) == 1
    assert len(list(memory.store.quads(None, PROV_WAS_REVISION_OF, None, EPISODES))) == 1
    assert memory.get("g1").end is None


def test_arguments_can_be_added_and_removed(memory: EpisodeMemory) -> None:
    memory.begin("handover", episode_id="h1")
    memory.add_argument("h1", role="object", value="cup", author="Alice")
    memory.add_argument("h1", role="recipient", value="Bob")
    assert memory.count(Cue("handover", obj="cup")) == 1
    gone = memory.remove_argument("h1", role="object", author="Alice")
    assert [a.value for a in gone] == ["cup"]
    assert memory.count(Cue("handover", obj="cup")) == 0
    assert [a.role for a in memory.get("h1").arguments] == ["recipient"]
    assert memory.get("h1").state_at_begin is not None
    with pytest.raises(NotFoundError):
        memory.remove_argument("h1", role="object")


@pytest.mark.parametrize(
    ("options", "field"),
    [
        ({"role": "", "value": "x"}, "role"),
        ({"role": "agent", "value": ""}, "value"),
        ({"role": "agent", "value": "x", "confidence": 1.5}, "confidence"),
        ({"role": "agent", "value": "x", "time": "yesterday"}, "time"),
        ({"role": "agent", "value": "Ann"}, "value"),  # already holds the role
    ],
)
def test_bad_arguments_name_the_field_and_change_nothing(
    memory: EpisodeMemory, options: dict, field: str
) -> None:
    memory.begin("wave", episode_id="w1", arguments=[ArgumentSpec("agent", "Ann")])
    before = len(memory.store)
    with pytest.raises(InvalidInputError) as caught:
        memory.add_argument("w1", **options)
    assert caught.value.field == field
    assert len(memory.store) == before


def test_roles_and_arguments_over_http(live_server: LiveServer) -> None:
    client = live_server.client
    for body in (
        {"id": "p1", "arguments": [{"role": "agent", "value": "HyungJin"}]},
        {
            "id": "p2",
            "arguments": [
                {"role": "agent", "value": "Maxime"},
                {"role": "recipient", "value": "HyungJin"},
            ],
        },
    ):
        answer = client.post("/episodes", json={"activity": "pointing", **body})
        assert answer.status_code == 201, answer.text
    cue = {"activity": "pointing", "agent": "HyungJin"}
    assert client.get("/episodes/count", params=cue).json() == {"count": 1}
    assert client.get("/episodes/recall", params=cue).json()["episode"]["id"] == "p1"
    recipient = {"activity": "pointing", "role": "recipient", "participant": "HyungJin"}
    assert client.get("/episodes/recall", params=recipient).json()["episode"]["id"] == "p2"
    added = client.post(
        "/episodes/p1/arguments",
        json={"role": "recipient", "value": "Maxime", "author": "vision", "confidence": 0.8},
    )
    assert added.status_code == 201 and added.json()["author"] == "vision"
    maxime = {"activity": "pointing", "role": "recipient", "participant": "Maxime"}
    assert client.get("/episodes/count", params=maxime).json() == {"count": 1}
    removed = client.delete("/episodes/p1/arguments/recipient", params={"author": "Alice"})
    assert removed.status_code == 200 and removed.json()[0]["value"] == "Maxime"
    assert client.get("/episodes/count", params=maxime).json() == {"count": 0}
    bad = client.post("/episodes/p1/arguments", json={"role": "agent", "value": "x", "conf": 1})
    assert bad.status_code == 422


def test_roles_and_arguments_on_the_command_line(tmp_path: Path) -> None:
    runner = CliRunner()
    data = ["--data", str(tmp_path)]
    assert runner.invoke(cli, ["init", *data]).exit_code == 0

    def run(*args: str) -> str:
        result = runner.invoke(cli, ["episodes", *args, *data])
        assert result.exit_code == 0, result.output
        return result.stdout

    run("begin", "greeting", "--id", "g1", "-a", "agent=unknown")
    run(
        "argument",
        "g1",
        "agent",
        "Martina",
        "--author",
        "face",
        "--confidence",
        "0.92",
        "--replace",
    )
    assert '"count": 1' in run("count", "greeting", "--agent", "Martina")
    assert '"count": 0' in run("count", "greeting", "--role", "agent", "--participant", "unknown")
    run("argument", "g1", "agent", "--remove")
    assert '"count": 0' in run("count", "greeting", "--agent", "Martina")
