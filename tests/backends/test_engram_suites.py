"""A subset of Engram's own directive, scene-memory and episode tests, run unchanged against a
server whose store is a memory on the SPARQL server under test (a fresh memory per module)."""

import os
import uuid
from collections.abc import Callable, Iterator
from typing import Any

import httpx
import pytest

from tests.api.armor.conftest import Armor, armor, loaded, ref, start_live_server
from tests.api.armor.test_commands import (
    test_add_then_query_returns_armor_strings,
    test_class_hierarchy_queries,
    test_object_properties_replace_and_remove,
    test_replace_and_remove_data_property,
)
from tests.api.armor.test_memory_directives import (
    test_memory_directive_errors_and_rollback,
    test_ten_scenes_learn_recognise_retrieve_sleep_and_pin,
)
from tests.conftest import LiveServer
from tests.episodes.test_integration import (
    recorded,
    test_record_query_replay_augment_rate_rank_delete,
)

pytestmark = pytest.mark.slow

__all__ = [
    "armor",
    "loaded",
    "recorded",
    "ref",
    "test_add_then_query_returns_armor_strings",
    "test_class_hierarchy_queries",
    "test_memory_directive_errors_and_rollback",
    "test_object_properties_replace_and_remove",
    "test_record_query_replay_augment_rate_rank_delete",
    "test_replace_and_remove_data_property",
    "test_ten_scenes_learn_recognise_retrieve_sleep_and_pin",
]


@pytest.fixture(scope="module")
def armor_server(
    tmp_path_factory: pytest.TempPathFactory, request: pytest.FixtureRequest
) -> Iterator[Armor]:
    """The ARMOR tests' server, its store a fresh memory on the SPARQL server."""
    url, profile = _target(request)
    with (
        start_live_server(
            tmp_path_factory.mktemp("armor-remote"),
            store_url=url,
            store_profile=profile,
            memory=f"armor-{uuid.uuid4().hex[:8]}",
        ) as running,
        httpx.Client(base_url=running.url, timeout=60) as http,
    ):
        yield Armor(http, running.url)


@pytest.fixture
def live_server(
    start_server: Callable[..., LiveServer], request: pytest.FixtureRequest
) -> LiveServer:
    """The episode tests' server, its store a fresh memory on the SPARQL server."""
    url, profile = _target(request)
    return start_server(
        store_url=url, store_profile=profile, memory=f"episodes-{uuid.uuid4().hex[:8]}"
    )


def _target(request: pytest.FixtureRequest) -> tuple[str, str]:
    external = os.environ.get("ENGRAM_TEST_SPARQL_URL")
    if external:
        return external, os.environ.get("ENGRAM_TEST_SPARQL_PROFILE", "oxigraph")
    server: Any = request.getfixturevalue("oxigraph_server")
    return server.url, "oxigraph"
