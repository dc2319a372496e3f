"""The backend conformance suite runs against a real ``oxigraph serve`` started here, and against
the server named by ``ENGRAM_TEST_SPARQL_URL`` (with ``ENGRAM_TEST_SPARQL_PROFILE``) if set."""

import os
import uuid
from collections.abc import Iterator

import pytest

from tests.backends.servers import OxigraphServer


@pytest.fixture(scope="session")
def oxigraph_server(tmp_path_factory: pytest.TempPathFactory) -> Iterator[OxigraphServer]:
    """One Oxigraph server for the session (each test uses memories of its own names)."""
    server = OxigraphServer(tmp_path_factory.mktemp("oxigraph") / "db").start()
    yield server
    server.stop()


def _targets() -> list[str]:
    return ["oxigraph"] + (["external"] if os.environ.get("ENGRAM_TEST_SPARQL_URL") else [])


@pytest.fixture(params=_targets())
def sparql_server(request: pytest.FixtureRequest) -> tuple[str, str]:
    """(URL, profile) of a SPARQL server under test."""
    if request.param == "external":
        url = os.environ["ENGRAM_TEST_SPARQL_URL"]
        return url, os.environ.get("ENGRAM_TEST_SPARQL_PROFILE", "oxigraph")
    server: OxigraphServer = request.getfixturevalue("oxigraph_server")
    return server.url, "oxigraph"


@pytest.fixture
def memory_name() -> str:
    """A memory name no other test uses."""
    return f"robot-{uuid.uuid4().hex[:12]}"
