"""One real Engram server per test module (loopback, on-disk store), and directive helpers.

``tests/conftest.py``'s ``live_server`` starts a server per test; the ARMOR tests share one per
module to stay fast, and isolate themselves by using a fresh reference name per test.
"""

import os
import tempfile
import uuid
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any

import httpx
import pytest

from api.config import Settings
from api.main import create_app
from api.protocol import ArmorDirectiveReq
from tests.conftest import RunningServer, free_port, serve

DATA = Path(__file__).parent / "data"
TEST_IRI = "http://www.semanticweb.org/emarolab/ontologies/armor-test"
Step = tuple[str, str, str, list[str]]
"""A directive as (command, primary spec, secondary spec, args)."""


def directive(
    command: str,
    first: str = "",
    second: str = "",
    args: list[str] | None = None,
    *,
    ref: str,
    client: str = "tester",
) -> dict[str, Any]:
    """One ``armor_msgs/ArmorDirectiveReq`` as JSON."""
    return {
        "client_name": client,
        "reference_name": ref,
        "command": command,
        "primary_command_spec": first,
        "secondary_command_spec": second,
        "args": args or [],
    }


def request(
    command: str,
    first: str = "",
    second: str = "",
    args: list[str] | None = None,
    *,
    ref: str,
    client: str = "tester",
) -> ArmorDirectiveReq:
    """One ``armor_msgs/ArmorDirectiveReq`` as the wire model (:func:`directive`'s fields)."""
    return ArmorDirectiveReq(**directive(command, first, second, args, ref=ref, client=client))


def directives(steps: list[Step], ref: str, client: str = "client") -> list[ArmorDirectiveReq]:
    """The requests of ``steps``, each to reference ``ref`` from ``client``."""
    return [request(*step, ref=ref, client=client) for step in steps]


class Armor:
    """Sends directives to a running server."""

    def __init__(self, http: httpx.Client, url: str) -> None:
        self.http = http
        self.url = url

    def call(
        self,
        command: str,
        first: str = "",
        second: str = "",
        args: list[str] | None = None,
        *,
        ref: str,
        client: str = "tester",
        values: str | None = None,
    ) -> dict[str, Any]:
        body = {"armor_request": directive(command, first, second, args, ref=ref, client=client)}
        params = {"values": values} if values else None
        response = self.http.post("/armor_interface_srv", json=body, params=params)
        assert response.status_code == 200, response.text
        result: dict[str, Any] = response.json()["armor_response"]
        return result

    def call_list(self, directives: list[dict[str, Any]]) -> dict[str, Any]:
        response = self.http.post(
            "/armor_interface_serialized_srv", json={"armor_requests": directives}
        )
        assert response.status_code == 200, response.text
        result: dict[str, Any] = response.json()
        return result

    def load_empty(
        self, ref: str, *, buffered: bool = False, buffered_reasoner: bool = True
    ) -> None:
        result = self.call(
            "LOAD",
            "FILE",
            "",
            ["", "http://ex.org/" + ref, str(buffered), "PELLET", str(buffered_reasoner)],
            ref=ref,
        )
        assert result["success"], result


def start_live_server(data_dir: Path, **overrides: Any) -> RunningServer:
    """A server over ``data_dir`` with the given settings overrides, which may LOAD and SAVE
    files in the temporary directory and the tests' data."""
    # the tests LOAD and SAVE files in their temporary directories and in DATA
    overrides.setdefault("armor_file_dirs", os.pathsep.join([tempfile.gettempdir(), str(DATA)]))
    settings = Settings(host="127.0.0.1", port=free_port(), data_dir=data_dir, **overrides)
    return serve(create_app(settings), settings)


@pytest.fixture(scope="module")
def armor_server(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Armor]:
    """A server over a fresh on-disk store, shared by the tests of one module."""
    with (
        start_live_server(tmp_path_factory.mktemp("armor")) as running,
        httpx.Client(base_url=running.url, timeout=60) as http,
    ):
        yield Armor(http, running.url)


@pytest.fixture
def armor(armor_server: Armor) -> Armor:
    return armor_server


@pytest.fixture
def ref() -> str:
    """A reference name no other test uses."""
    return "ref_" + uuid.uuid4().hex[:10]


@pytest.fixture
def loaded(armor: Armor, ref: str) -> Callable[..., str]:
    """Load an empty reference (unbuffered manipulation by default) and return its name."""

    def load(**flags: bool) -> str:
        armor.load_empty(ref, **flags)
        return ref

    return load
