"""The MCAP read limit as a setting (``ENGRAM_MCAP_READ_LIMIT_BYTES``): it reaches the
episodes' readers, so a lower limit refuses a recording a higher one replays, and a limit above
each chunk replays a recording however many chunks it reads at once."""

from pathlib import Path

import numpy as np
import pytest
from pydantic import ValidationError

from api.config import Settings
from api.services import open_services
from episodes.streams import CorruptRecordingError, Recorder

IMAGE = np.random.default_rng(3).integers(0, 256, (240, 320, 3), dtype=np.uint8)  # 230 KB


def _replay(data_dir: Path) -> int:
    """Frames replayed from the episode ``ep-1`` of the memory in ``data_dir``, whose
    settings come from the environment."""
    with open_services(Settings(data_dir=data_dir), create=True) as services:
        return sum(1 for _ in services.episodes.replayer("ep-1").frames())


def test_a_lower_limit_refuses_a_recording_a_higher_one_replays(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    with open_services(Settings(data_dir=tmp_path), create=True) as services:
        recorder = Recorder(services.episodes.streams_path("ep-1"), episode_id="ep-1")
    recorder.add_provider("cam", "image", encoding="rgb8")
    for k in range(12):  # three chunks of about 1.1 MB
        recorder.tick({"cam": IMAGE}, time_ns=1_000_000_000 + k)
    recorder.close()

    monkeypatch.setenv("ENGRAM_MCAP_READ_LIMIT_BYTES", str(2 * 1024**2))
    assert _replay(tmp_path) == 12
    monkeypatch.setenv("ENGRAM_MCAP_READ_LIMIT_BYTES", str(512 * 1024))
    with pytest.raises(CorruptRecordingError, match="over the limit 524288"):
        _replay(tmp_path)


@pytest.mark.parametrize("value", ["0", "-1", "a lot"])
def test_a_bad_limit_is_refused_naming_the_setting(
    value: str, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setenv("ENGRAM_MCAP_READ_LIMIT_BYTES", value)
    with pytest.raises(ValidationError) as caught:
        Settings()
    assert caught.value.errors()[0]["loc"] == ("mcap_read_limit_bytes",)
