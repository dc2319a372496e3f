"""The README's commands and its worked example still work."""

import os
import re
import shlex
import subprocess
import sys
from pathlib import Path

import httpx
import pytest

from tests.conftest import LiveServer

ROOT = Path(__file__).resolve().parents[1]
README = (ROOT / "README.md").read_text(encoding="utf-8")


def _blocks(language: str) -> list[str]:
    """The fenced code blocks tagged ``language`` ("" for untagged), in order."""
    found = re.findall(r"^```(\w*)\n(.*?)^```$", README, flags=re.DOTALL | re.MULTILINE)
    return [body for tag, body in found if tag == language]


def test_the_two_commands_are_scripts_that_exist() -> None:
    commands = [line.split("#")[0].strip() for line in _blocks("sh")[0].splitlines()]
    assert commands == ["bash scripts/demo", "bash scripts/test"]
    for command in commands:
        assert (ROOT / command.split()[1]).is_file()


def test_ci_runs_the_readme_test_command() -> None:
    assert "scripts/test" in (ROOT / ".ci" / "run").read_text(encoding="utf-8")


def test_the_worked_example_answers_as_shown(live_server: LiveServer) -> None:
    curl = shlex.split(_blocks("sh")[1].replace("\\\n", " "))
    query = curl[curl.index("--data-urlencode") + 1].removeprefix("query=")
    accept = curl[curl.index("-H") + 1].split(": ", 1)[1]
    answer = httpx.get(
        live_server.url + "/sparql", params={"query": query}, headers={"Accept": accept}
    )
    expected = _blocks("")[0]
    assert answer.text.replace("\r\n", "\n") == expected


def test_the_client_example_learns_the_class_the_readme_names(
    live_server: LiveServer, capsys: pytest.CaptureFixture[str]
) -> None:
    code = _blocks("python")[0].replace("http://127.0.0.1:8000", live_server.url)
    exec(compile(code, "README.md", "exec"), {})
    assert capsys.readouterr().out.strip() == "['true'] ['4']"


def test_perceive_on_a_real_scan_prints_what_the_readme_shows(tmp_path: Path) -> None:
    """The README's ``console`` block: ``engram perceive`` on a real scan with no pose, run as
    shown (through the installed executable), prints the block's output lines."""
    (block,) = _blocks("console")
    commands = [line[2:] for line in block.splitlines() if line.startswith("$ ")]
    shown = [line for line in block.splitlines() if not line.startswith("$ ")]
    engram = str(Path(sys.executable).with_name("engram"))
    env = {**os.environ, "ENGRAM_DATA_DIR": str(tmp_path / "data"), "COLUMNS": "1000"}
    printed = ""
    for command in commands:
        args = shlex.split(command)
        assert args[0] == "engram"
        run = subprocess.run(
            [engram, *args[1:]], cwd=ROOT, env=env, capture_output=True, text=True, timeout=300
        )
        assert run.returncode == 0, run.stderr
        printed = run.stdout
    assert printed.splitlines() == shown
