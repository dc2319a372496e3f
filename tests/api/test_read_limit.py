"""The MCAP read limit as a setting (``ENGRAM_MCAP_READ_LIMIT_BYTES``): it reaches the
episodes' readers, so a lower limit refuses a recording a higher one replays, and a limit above
each chunk replays a recording however many chunks it reads at once."""

from collections.abc import Callable
from pathlib import Path

import numpy as np
import pytest
from pydantic import ValidationError

from api.config import Settings
from api.services import open_services
from episodes.streams import CorruptRecordingError, Recorder
from tests.conftest import LiveServer

IMAGE = np.random.default_rng(3).integers(0, 256, (240, 320, 3), dtype=np.uint8)  # 230 KB


def _replay(data_dir: Path) -> int:
    """Frames replayed from the episode ``ep-1`` of the memory in ``data_dir``, whose
    settings come from the environment."""
    with open_services(Settings(data_dir=data_dir), create=True) as services:
        return sum(1 for _ in services.episodes.streams.replayer("ep-1").frames())


def _record(data_dir: Path) -> None:
    """Episode ``ep-1``'s recording in the memory at ``data_dir``: twelve images and twelve
    arrays of 20,000 numbers, each a chunk of about 200 KB, replayed as one run of about 5 MB
    read at once."""
    with open_services(Settings(data_dir=data_dir), create=True) as services:
        recorder = Recorder(services.episodes.streams.path("ep-1"), episode_id="ep-1")
    recorder.add_provider("cam", "image", encoding="rgb8")
    recorder.add_provider("arm", "float_array", dtype="float64")
    for k in range(12):
        recorder.tick({"cam": IMAGE, "arm": np.full(20_000, k / 10)}, time_ns=1_000_000_000 + k)
    recorder.close()


def test_a_lower_limit_refuses_a_recording_a_higher_one_replays(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    _record(tmp_path)
    monkeypatch.setenv("ENGRAM_MCAP_READ_LIMIT_BYTES", str(1024**2))
    assert _replay(tmp_path) == 12
    monkeypatch.setenv("ENGRAM_MCAP_READ_LIMIT_BYTES", str(128 * 1024))
    with pytest.raises(CorruptRecordingError, match="over the limit 131072"):
        _replay(tmp_path)


@pytest.mark.parametrize(("limit", "status"), [(1024**2, 200), (128 * 1024, 409)])
def test_the_views_read_within_the_server_s_limit(
    tmp_path: Path, start_server: Callable[..., LiveServer], limit: int, status: int
) -> None:
    _record(tmp_path)
    client = start_server(data_dir=tmp_path, mcap_read_limit_bytes=limit).client
    channels = client.get("/views/episodes/ep-1/channels")  # from the summary alone
    assert channels.status_code == 200, channels.text
    plot = client.get("/views/episodes/ep-1/plot", params={"channel": "arm"})
    assert plot.status_code == status, plot.text


@pytest.mark.parametrize("value", ["0", "-1", "a lot"])
def test_a_bad_limit_is_refused_naming_the_setting(
    value: str, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setenv("ENGRAM_MCAP_READ_LIMIT_BYTES", value)
    with pytest.raises(ValidationError) as caught:
        Settings()
    assert caught.value.errors()[0]["loc"] == ("mcap_read_limit_bytes",)
