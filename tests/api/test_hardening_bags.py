"""Bag imports under attack: compression bombs stop at the decompression limit, a tar bomb at
the unpacking limit, and a damaged bag answers 422 naming the bag and the problem; nothing
stays behind."""

from collections.abc import Callable
from pathlib import Path

import httpx
import numpy as np
import pytest
from typer.testing import CliRunner

from api.cli import app as cli
from episodes import EpisodeMemory
from episodes.bag_limits import DamagedBagError, DecompressionLimitError
from kg import Store, ensure_ontology
from shapes import Frame
from shapes.bags import write_bag
from tests.api.bags_hostile import (
    patch_mcap_header_length,
    patch_ros1,
    ros1_bag,
    ros2_bag,
    tar_of,
)
from tests.conftest import LiveServer

LIMIT = 1024 * 1024
BOMB = 8 * LIMIT  # what the bombs expand to


@pytest.fixture(scope="module")
def server(start_module_server: Callable[..., LiveServer]) -> LiveServer:
    """A server whose bag pieces may expand to 1 MiB."""
    return start_module_server(max_decompressed_bytes=LIMIT)


def _upload(server: LiveServer, body: bytes, episode_id: str) -> httpx.Response:
    return server.client.post(
        "/episodes/import/upload", params={"activity": "said", "id": episode_id}, content=body
    )


def _nothing_left(server: LiveServer, episode_id: str) -> None:
    data = server.settings.data_dir
    assert not any((data / "uploads").iterdir())
    assert not (data / "streams" / episode_id).exists()
    assert server.client.get(f"/episodes/{episode_id}").status_code == 404


@pytest.mark.parametrize("compression", ["bz2", "lz4"])
def test_a_ros1_bomb_stops_at_the_decompression_limit(
    server: LiveServer, tmp_path: Path, compression: str
) -> None:
    bag = ros1_bag(tmp_path / "bomb.bag", text_bytes=BOMB, compression=compression)
    assert bag.stat().st_size < BOMB / 100
    answer = _upload(server, bag.read_bytes(), f"bomb-{compression}")
    assert answer.status_code == 422, answer.text
    body = answer.json()
    assert body["error"] == "DecompressionLimitError"
    assert "the uploaded bag" in body["detail"] and f"limit of {LIMIT} bytes" in body["detail"]
    _nothing_left(server, f"bomb-{compression}")


@pytest.mark.parametrize("mode", ["message", "file"])
def test_a_ros2_zstd_bomb_stops_at_the_decompression_limit(
    server: LiveServer, tmp_path: Path, mode: str
) -> None:
    bag = ros2_bag(
        tmp_path / "bomb",
        text_bytes=BOMB,
        zstd_messages=mode == "message",
        zstd_file=mode == "file",
    )
    body = tar_of(bag)
    assert len(body) < BOMB / 10
    answer = _upload(server, body, f"bomb-zstd-{mode}")
    assert answer.status_code == 422, answer.text
    assert answer.json()["error"] == "DecompressionLimitError"
    _nothing_left(server, f"bomb-zstd-{mode}")


def test_a_bag_within_the_limit_is_imported(server: LiveServer, tmp_path: Path) -> None:
    bag = ros1_bag(tmp_path / "fine.bag", text_bytes=LIMIT // 2, compression="bz2")
    answer = _upload(server, bag.read_bytes(), "fine")
    assert answer.status_code == 201, answer.text
    assert answer.json()["streams"][0]["count"] == 1


def test_a_compressed_tar_stops_unpacking_at_the_limit(server: LiveServer, tmp_path: Path) -> None:
    """The tar.xz bomb: a few KB that would unpack to 8 MiB, over the 1 MiB limit."""
    bag = ros2_bag(tmp_path / "big", text_bytes=100)
    (bag / "padding").write_bytes(b"\0" * BOMB)
    body = tar_of(bag, "w:xz")
    assert len(body) < 100_000
    answer = _upload(server, body, "tarbomb")
    assert answer.status_code == 422, answer.text
    assert answer.json()["field"] == "body"
    assert f"more than {LIMIT} bytes" in answer.json()["value"]
    _nothing_left(server, "tarbomb")


# (what is damaged, ROS 1 record op, field, value)
DAMAGED = [
    ("message length 0xFFFFFFF0", 2, "data_len", 0xFFFFFFF0),
    ("index count 2^31", 4, "count", 2**31),
    ("chunk length 10", 5, "data_len", 10),
    ("connection count 2^31", 6, "count", 2**31),
]


@pytest.mark.parametrize(("damage", "op", "field", "value"), DAMAGED, ids=[d[0] for d in DAMAGED])
def test_a_damaged_ros1_bag_answers_422_naming_it(
    server: LiveServer, tmp_path: Path, damage: str, op: int, field: str, value: int
) -> None:
    bag = ros1_bag(tmp_path / "damaged.bag", text_bytes=100)
    patch_ros1(bag, op, field, value)
    episode_id = f"damaged-{op}-{field}"
    answer = _upload(server, bag.read_bytes(), episode_id)
    assert answer.status_code == 422, answer.text
    assert answer.json()["error"] == "DamagedBagError"
    assert "the uploaded bag" in answer.json()["detail"]
    _nothing_left(server, episode_id)
    # the same bag imported by path names its path inside the data directory
    inside = server.settings.data_dir / "bags" / f"{episode_id}.bag"
    inside.parent.mkdir(exist_ok=True)
    inside.write_bytes(bag.read_bytes())
    by_path = server.client.post(
        "/episodes/import", json={"path": f"bags/{episode_id}.bag", "activity": "said"}
    )
    assert by_path.status_code == 422, by_path.text
    assert f"bags/{episode_id}.bag" in by_path.json()["detail"]
    assert str(server.settings.data_dir) not in by_path.text


def test_an_mcap_record_length_of_2_62_answers_422(server: LiveServer, tmp_path: Path) -> None:
    bag = ros2_bag(tmp_path / "long", text_bytes=100, mcap=True)
    patch_mcap_header_length(bag, 2**62)
    answer = _upload(server, tar_of(bag), "mcap-long")
    assert answer.status_code == 422, answer.text
    assert answer.json()["error"] == "DamagedBagError"
    _nothing_left(server, "mcap-long")


def test_the_python_api_raises_the_limit_error(tmp_path: Path) -> None:
    store = Store(tmp_path / "store")
    ensure_ontology(store)
    memory = EpisodeMemory(store, data_dir=tmp_path)
    try:
        bag = ros1_bag(tmp_path / "bomb.bag", text_bytes=BOMB, compression="bz2")
        with pytest.raises(DecompressionLimitError, match=r"bomb\.bag"):
            memory.imports.bag_report(bag, "said", max_decompressed_bytes=LIMIT)
        assert isinstance(DecompressionLimitError("x"), DamagedBagError)
        assert not (tmp_path / "streams").exists() or not any((tmp_path / "streams").iterdir())
    finally:
        memory.close()


@pytest.mark.parametrize(
    ("damage", "op", "field", "value"), DAMAGED[:2], ids=[d[0] for d in DAMAGED[:2]]
)
def test_the_cli_says_what_is_damaged_in_one_line(
    tmp_path: Path, damage: str, op: int, field: str, value: int
) -> None:
    bag = ros1_bag(tmp_path / "damaged.bag", text_bytes=100)
    patch_ros1(bag, op, field, value)
    data = ["--data", str(tmp_path / "data")]
    assert CliRunner().invoke(cli, ["init", *data]).exit_code == 0
    result = CliRunner().invoke(cli, ["episodes", "import", str(bag), "said", *data])
    assert result.exit_code != 0
    assert result.exception is None or isinstance(result.exception, SystemExit)
    # one line for the error, after the line that names the memory opened
    lines = [line for line in result.output.strip().splitlines() if not line.startswith("memory:")]
    assert len(lines) == 1 and "damaged.bag" in lines[0], result.output
    assert "Traceback" not in result.output


@pytest.mark.parametrize(
    ("damage", "op", "field", "value"), DAMAGED[:2], ids=[d[0] for d in DAMAGED[:2]]
)
def test_engram_perceive_says_what_is_damaged_in_one_line(
    tmp_path: Path, damage: str, op: int, field: str, value: int
) -> None:
    points = np.random.default_rng(29).uniform(-1, 1, size=(50, 3))
    bag = tmp_path / "cloud.bag"
    write_bag(bag, [Frame(points, None, 1.0, "camera", np.eye(4))], ros=1)
    patch_ros1(bag, op, field, value)
    result = CliRunner().invoke(
        cli, ["perceive", str(bag), "--local", "--data", str(tmp_path / "data")]
    )
    assert result.exit_code != 0
    assert result.exception is None or isinstance(result.exception, SystemExit), result.output
    assert "cloud.bag" in result.output and "Traceback" not in result.output
