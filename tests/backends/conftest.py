"""The backend conformance suite runs against a real ``oxigraph serve`` started here, and against
the server named by ``ENGRAM_TEST_SPARQL_URL`` (with ``ENGRAM_TEST_SPARQL_PROFILE``) if set."""

import os
import uuid
from collections.abc import Iterator

import pytest

from tests.backends.servers import MotoServer, OxigraphServer


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


@pytest.fixture(scope="session")
def s3_server() -> Iterator[MotoServer]:
    """moto's S3 server for the session, with test credentials in the environment."""
    saved = {k: os.environ.get(k) for k in _AWS}
    os.environ.update(_AWS)
    server = MotoServer().start()
    yield server
    server.stop()
    for key, value in saved.items():
        if value is None:
            os.environ.pop(key, None)
        else:
            os.environ[key] = value


_AWS = {
    "AWS_ACCESS_KEY_ID": "engram-test",
    "AWS_SECRET_ACCESS_KEY": "engram-test",
    "AWS_DEFAULT_REGION": "us-east-1",
}
