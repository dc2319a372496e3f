"""``engram episodes ...`` run in-process with typer's runner over an on-disk store."""

import json
from pathlib import Path

import pytest
from typer.testing import CliRunner

from api.cli import app

runner = CliRunner()
NOW = "2026-02-26T10:00:00+00:00"


def engram(data: Path, *arguments: str) -> tuple[int, str]:
    made = runner.invoke(app, ["init", "--data", str(data)])
    assert made.exit_code == 0, made.output
    result = runner.invoke(app, ["episodes", *arguments, "--data", str(data)])
    # stdout is the JSON; stderr says which memory was opened, and why a command failed
    return result.exit_code, result.stdout if result.exit_code == 0 else result.output


def test_begin_end_recall_count_delete(tmp_path: Path) -> None:
    code, out = engram(
        tmp_path,
        "begin",
        "babbling",
        "--type",
        "action",
        "-a",
        "agent=HyungJin",
        "-a",
        "object=left hand",
        "--at",
        "2026-01-26T15:30:00+00:00",
        "--id",
        "ep1",
    )
    assert code == 0, out
    assert json.loads(out)["arguments"][0]["value"] == "HyungJin"
    code, out = engram(tmp_path, "end", "ep1", "--at", "2026-01-26T15:35:00+00:00")
    assert code == 0, out
    code, out = engram(tmp_path, "recall", "babbling", "--agent", "HyungJin", "--now", NOW)
    assert code == 0, out
    assert json.loads(out)["when"] == "one month ago, on January 26th"
    code, out = engram(tmp_path, "count", "babbling", "--object", "left hand")
    assert json.loads(out) == {"count": 1}
    code, out = engram(tmp_path, "annotate", "ep1", "comment", "went well", "--confidence", "0.9")
    assert code == 0 and json.loads(out)["confidence"] == 0.9
    code, out = engram(tmp_path, "delete", "ep1")
    assert code == 0 and "deleted" in out
    code, out = engram(tmp_path, "show", "ep1")
    assert code == 1 and "ep1" in out


@pytest.mark.parametrize(
    ("arguments", "code", "fragment"),
    [
        (["begin", "x", "--at", "2026-01-26T15:30:00"], 2, "begin: got '2026-01-26T15:30:00'"),
        (["begin", "x", "-a", "agent"], 2, "ROLE=VALUE"),
        (["recall", "x", "--which", "nth", "--n", "0"], 2, "n: got 0"),
        (["recall", "x", "--now", "later"], 2, "now: got 'later'"),
        (["recall", "nothing"], 1, "nothing"),
        (["between", "2026-01-02T00:00:00Z", "2026-01-01T00:00:00Z"], 2, "end: got"),
        (["end", "nope"], 1, "nope"),
        (["rank", "edges", "--alpha", "3"], 2, "alpha"),
    ],
)
def test_bad_input_exits_with_a_message_naming_the_field(
    tmp_path: Path, arguments: list[str], code: int, fragment: str
) -> None:
    exit_code, out = engram(tmp_path, *arguments)
    assert exit_code == code, out
    assert fragment in out


def test_export_and_import_of_one_episode(tmp_path: Path) -> None:
    code, out = engram(tmp_path / "a", "begin", "wave", "--id", "w1", "-a", "agent=NAO")
    assert code == 0, out
    target = tmp_path / "w1.trig"
    code, out = engram(tmp_path / "a", "export-rdf", "w1", "-o", str(target))
    assert code == 0 and target.is_file(), out
    code, out = engram(tmp_path / "b", "import-rdf", str(target))
    assert code == 0, out
    assert json.loads(out)["arguments"][0]["value"] == "NAO"
    code, out = engram(tmp_path / "b", "import-rdf", str(tmp_path / "missing.trig"))
    assert code == 1 and "missing.trig" in out


def test_a_rating_session_as_a_feedback_episode(tmp_path: Path) -> None:
    assert engram(tmp_path, "begin", "babbling", "--id", "b1")[0] == 0
    code, out = engram(tmp_path, "feedback", "Martina", "--rated", "b1", "--id", "fb1")
    assert code == 0, out
    assert json.loads(out)["activity"] == "feedback"
    code, out = engram(tmp_path, "rate", "b1", "0123abcd", "Alice", "8", "--session", "fb1")
    assert code == 2 and "person" in out and "Martina" in out
    code, out = engram(tmp_path, "session-ratings", "fb1")
    assert (code, json.loads(out)) == (0, [])
    code, out = engram(tmp_path, "recall", "feedback", "--agent", "Martina")
    assert code == 0 and "fb1" in out
