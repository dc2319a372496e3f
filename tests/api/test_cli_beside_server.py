"""The ``engram`` executable on one data directory, with and without a server running on it:
every command opens the same memory, says which, and talks to the server that holds it."""

import json
import os
import signal
import subprocess
import sys
import time
from collections.abc import Iterator
from pathlib import Path

import httpx
import pytest

from tests.api.bags_hostile import ros1_bag
from tests.conftest import free_port

ENGRAM = str(Path(sys.executable).with_name("engram"))


def engram(*arguments: str, env: dict[str, str] | None = None) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [ENGRAM, *arguments],
        capture_output=True,
        text=True,
        timeout=120,
        env={**os.environ, **(env or {})},
        check=False,
    )


@pytest.fixture
def served(tmp_path: Path) -> Iterator[tuple[Path, str]]:
    """A data directory with an `engram serve --init` running on it, and its URL."""
    data = tmp_path / "data"
    port = free_port()
    url = f"http://127.0.0.1:{port}"
    server = subprocess.Popen(
        [ENGRAM, "serve", "--init", "--data", str(data), "--port", str(port)],
        stdout=subprocess.DEVNULL,
        stderr=subprocess.PIPE,
        text=True,
    )
    try:
        deadline = time.monotonic() + 90
        while time.monotonic() < deadline:
            try:
                if httpx.get(f"{url}/health", timeout=2).json()["status"] == "ok":
                    break
            except httpx.HTTPError:
                pass
            assert server.poll() is None, server.stderr.read() if server.stderr else ""
            time.sleep(0.3)
        else:
            pytest.fail("the server did not come up")
        yield data, url
    finally:
        server.send_signal(signal.SIGINT)
        _, stderr = server.communicate(timeout=60)
    assert server.returncode == 0
    assert "Traceback" not in stderr  # Ctrl-C stops the server and its query workers quietly
    assert not (data / "server.json").exists()  # withdrawn when the server stopped


@pytest.mark.slow
def test_every_command_talks_to_the_server_that_holds_the_data_directory(
    served: tuple[Path, str], tmp_path: Path
) -> None:
    data, url = served
    assert json.loads((data / "server.json").read_text())["url"] == url
    where = ["--data", str(data)]
    begun = engram(
        "episodes", "begin", "pointing", "-a", "agent=Maxime", "-a", "recipient=HyungJin", *where
    )
    assert begun.returncode == 0, begun.stderr
    assert f"memory: the Engram server at {url}" in begun.stderr
    counted = engram(
        "episodes", "count", "pointing", "--role", "recipient", "--participant", "HyungJin", *where
    )
    assert (counted.returncode, json.loads(counted.stdout)) == (0, {"count": 1}), counted.stderr
    # the server answers the same: one memory
    params = {"activity": "pointing", "role": "recipient", "participant": "HyungJin"}
    assert httpx.get(f"{url}/episodes/count", params=params).json() == {"count": 1}

    target = tmp_path / "engram.owl"
    exported = engram("export", "-o", str(target), *where)
    assert exported.returncode == 0, exported.stderr
    assert b"owl:Ontology" in target.read_bytes() or b"Ontology" in target.read_bytes()
    info = engram("info", *where)
    assert info.returncode == 0 and '"status": "ok"' in info.stdout, info.stderr
    asked = engram("ask", "how many times did Maxime do pointing", *where)
    assert asked.returncode == 0 and "Maxime did pointing once" in asked.stdout, asked.stderr

    copy = tmp_path / "copy"
    backed = engram("backup", str(copy), *where)
    assert backed.returncode == 0, backed.stderr
    assert (copy / "CURRENT").exists()  # a store directory

    bag = ros1_bag(tmp_path / "said.bag", text_bytes=3 << 20)  # sent in several chunks
    imported = engram("episodes", "import", str(bag), "said", "--id", "s1", *where)
    assert imported.returncode == 0, imported.stderr
    assert f"memory: the Engram server at {url}" in imported.stderr
    assert httpx.get(f"{url}/episodes/s1").json()["activity"] == "said"

    checked = engram("check", *where)
    assert checked.returncode == 1 and url in checked.stderr  # check needs the store to itself


def test_a_missing_memory_is_an_error_not_a_new_empty_one(tmp_path: Path) -> None:
    typo = tmp_path / "typo"
    for command in (["info"], ["check"], ["episodes", "count", "pointing"], ["export", "-o", "x"]):
        result = engram(*command, "--data", str(typo))
        assert result.returncode == 1, (command, result.stderr)
        assert f"no memory in {typo}" in result.stderr
    assert not typo.exists()
    served = engram("serve", "--data", str(typo))
    assert served.returncode == 1 and "--init" in served.stderr


def test_every_command_names_the_memory_it_opened(tmp_path: Path) -> None:
    data = tmp_path / "data"
    made = engram("init", "--data", str(data))
    assert made.returncode == 0 and "now holds an empty memory" in made.stdout, made.stderr
    again = engram("init", "--data", str(data))
    assert "holds a memory already" in again.stdout
    from_env = engram("episodes", "count", "pointing", env={"ENGRAM_DATA_DIR": str(data)})
    assert from_env.returncode == 0, from_env.stderr
    assert f"memory: {data}" in from_env.stderr
    assert json.loads(from_env.stdout) == {"count": 0}


def test_a_bad_port_is_one_line_naming_the_range(tmp_path: Path) -> None:
    result = engram("serve", "--init", "--data", str(tmp_path / "d"), "--port", "99999")
    assert result.returncode == 2
    assert "'--port'" in result.stderr and "65535" in result.stderr
    assert "Traceback" not in result.stderr and "pydantic" not in result.stderr


def test_a_backup_restores_as_the_data_directorys_memory(tmp_path: Path) -> None:
    data, copy = tmp_path / "data", tmp_path / "copy"
    where = ["--data", str(data)]
    assert engram("init", *where).returncode == 0
    assert engram("episodes", "begin", "pointing", *where).returncode == 0
    assert engram("backup", str(copy), *where).returncode == 0
    assert engram("episodes", "begin", "pointing", *where).returncode == 0
    restored = engram("restore", str(copy), *where)
    assert restored.returncode == 0, restored.stderr
    assert "kept in" in restored.stdout
    counted = engram("episodes", "count", "pointing", *where)
    assert json.loads(counted.stdout) == {"count": 1}
    (kept,) = (data / "backups").glob("before-restore-*")
    assert (kept / "CURRENT").exists()
    refused = engram("restore", str(tmp_path / "nothing"), *where)
    assert refused.returncode == 1 and "nothing" in refused.stderr
