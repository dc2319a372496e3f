"""ARMOR's file commands on the server: LOAD FILE, SAVE and LOG FILE stay inside the data
directory (and armor_file_dirs), LOAD WEB fetches only under armor_url_prefixes, and a path with
a control character is refused."""

import logging
from collections.abc import Iterator
from pathlib import Path

import httpx
import pytest

from api.config import Settings
from api.main import create_app
from tests.api.armor.conftest import Armor
from tests.conftest import free_port, serve

TTL = "@prefix owl: <http://www.w3.org/2002/07/owl#> .\n<http://ex.org/t#A> a owl:Class .\n"
RESOURCE_ERROR, INVALID_ARGUMENTS = 209, 208


@pytest.fixture(scope="module")
def confined(tmp_path_factory: pytest.TempPathFactory) -> Iterator[tuple[Armor, Settings]]:
    """A server with the default file policy; LOAD WEB may fetch its own /export only."""
    port = free_port()
    settings = Settings(
        host="127.0.0.1",
        port=port,
        data_dir=tmp_path_factory.mktemp("armor-files"),
        armor_url_prefixes=f"http://127.0.0.1:{port}/export",
    )
    with (
        serve(create_app(settings), settings) as running,
        httpx.Client(base_url=running.url, timeout=60) as http,
    ):
        yield Armor(http, running.url), settings
    for handler in logging.getLogger("api.armor").handlers:  # LOG FILE ON's, if a test failed
        handler.close()


def _load(armor: Armor, path: str, ref: str, web: bool = False) -> dict[str, object]:
    spec = "WEB" if web else "FILE"
    return armor.call("LOAD", spec, "", [path, "http://ex.org/t", "false", "", "true"], ref=ref)


def _refs(armor: Armor) -> list[str]:
    return list(armor.call("GET", "ALL", "REFS", [], ref="logs")["queried_objects"])  # type: ignore[arg-type]


@pytest.mark.parametrize("path", ["/etc/passwd", "../../../../../../etc/passwd"])
def test_load_file_outside_the_data_directory_is_refused(
    confined: tuple[Armor, Settings], path: str
) -> None:
    armor, _ = confined
    result = _load(armor, path, "outside")
    assert (result["success"], result["exit_code"]) == (False, RESOURCE_ERROR), result
    assert "outside the directories" in str(result["error_description"])
    assert "root:" not in str(result["error_description"])  # nothing of the file echoed
    assert "outside" not in _refs(armor)


def test_a_symbolic_link_out_of_the_data_directory_is_refused(
    confined: tuple[Armor, Settings], tmp_path: Path
) -> None:
    armor, settings = confined
    secret = tmp_path / "secret.ttl"
    secret.write_text(TTL)
    (settings.data_dir / "link.ttl").symlink_to(secret)
    result = _load(armor, str(settings.data_dir / "link.ttl"), "linked")
    assert (result["success"], result["exit_code"]) == (False, RESOURCE_ERROR), result


def test_files_inside_the_data_directory_load_and_save(
    confined: tuple[Armor, Settings], tmp_path: Path
) -> None:
    armor, settings = confined
    (settings.data_dir / "onto").mkdir()
    (settings.data_dir / "onto" / "t.ttl").write_text(TTL)
    assert _load(armor, "onto/t.ttl", "inside")["success"]
    assert armor.call("SAVE", "", "", ["onto/saved.ttl"], ref="inside")["success"]
    assert "t#A" in (settings.data_dir / "onto" / "saved.ttl").read_text()
    refused = armor.call("SAVE", "", "", [str(tmp_path / "out.ttl")], ref="inside")
    assert (refused["success"], refused["exit_code"]) == (False, RESOURCE_ERROR)
    assert not (tmp_path / "out.ttl").exists()


def test_log_file_stays_inside_and_refuses_control_characters(
    confined: tuple[Armor, Settings], tmp_path: Path
) -> None:
    armor, settings = confined
    outside = tmp_path / "made" / "armor.log"
    result = armor.call("LOG", "FILE", "ON", [str(outside)], ref="logs")
    assert (result["success"], result["exit_code"]) == (False, RESOURCE_ERROR), result
    assert not (tmp_path / "made").exists()
    forged = armor.call("LOG", "FILE", "ON", ["a.log\n2026-01-01 INFO forged"], ref="logs")
    assert (forged["success"], forged["exit_code"]) == (False, INVALID_ARGUMENTS), forged
    assert armor.call("LOG", "FILE", "ON", ["logs/armor.log"], ref="logs")["success"]
    assert (settings.data_dir / "logs" / "armor.log").is_file()
    assert armor.call("LOG", "FILE", "OFF", [], ref="logs")["success"]


def test_load_web_fetches_only_under_the_allowed_prefixes(
    confined: tuple[Armor, Settings],
) -> None:
    armor, settings = confined
    own = f"http://127.0.0.1:{settings.port}"
    refused = _load(armor, f"{own}/health", "web_refused", web=True)
    assert (refused["success"], refused["exit_code"]) == (False, RESOURCE_ERROR), refused
    assert "armor_url_prefixes" in str(refused["error_description"])
    lookalike = _load(armor, f"{own}/exports-elsewhere", "web_lookalike", web=True)
    assert lookalike["exit_code"] == RESOURCE_ERROR
    allowed = _load(armor, f"{own}/export?format=turtle", "web_allowed", web=True)
    assert allowed["success"], allowed


def test_load_web_is_refused_when_no_prefix_is_set(tmp_path: Path) -> None:
    settings = Settings(host="127.0.0.1", port=free_port(), data_dir=tmp_path / "data")
    with serve(create_app(settings), settings) as running:
        url = running.url
        with httpx.Client(base_url=url, timeout=60) as http:
            result = _load(Armor(http, url), f"{url}/export", "web", web=True)
        assert (result["success"], result["exit_code"]) == (False, RESOURCE_ERROR), result
