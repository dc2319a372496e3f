"""A server opened on a store whose REASON was killed mid-write serves no partial closure."""

import signal
import subprocess
import sys
from collections.abc import Callable
from pathlib import Path

from api.config import Settings
from tests.conftest import LiveServer
from tests.reasoners.owl_rl.conftest import KILLED_REASON

COUNT = "SELECT (COUNT(*) AS ?n) WHERE { GRAPH <%s> { ?s ?p ?o } }"
REF = "https://w3id.org/engram/graph/ref/onto"


def _count(server: LiveServer, graph: str) -> int:
    answer = server.client.get("/sparql", params={"query": COUNT % graph})
    assert answer.status_code == 200, answer.text
    return int(answer.json()["results"]["bindings"][0]["n"]["value"])


def test_the_server_clears_a_closure_whose_bulk_write_was_killed(
    tmp_path: Path, start_server: Callable[..., LiveServer]
) -> None:
    data_dir = tmp_path / "data"
    store_dir = Settings(data_dir=data_dir).store_dir
    killed = subprocess.run(
        [sys.executable, "-c", KILLED_REASON, str(store_dir), "onto"],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert killed.returncode == -signal.SIGKILL, killed.stderr
    server = start_server(data_dir=data_dir)
    assert _count(server, REF + "/inferred") == 0, "the half-written closure is gone"
    assert _count(server, REF) > 3_000 * 0.9, "the committed assertions are kept"
    assert _count(server, "https://w3id.org/engram/graph/bulk-writes") == 0
