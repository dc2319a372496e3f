"""Recordings with every kind of channel, and the samples that went into them."""

from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from episodes.streams import Recorder

JOINTS = ["neck_pitch", "neck_roll", "neck_yaw", "eyes_tilt"]
SKIN_BASELINE = 5.0


def make_recorder(path: Path, **options: Any) -> Recorder:
    """A recorder with one provider of each kind (the skin is baseline-filtered)."""
    rec = Recorder(path, episode_id=path.name, **options)
    rec.add_provider("icub/head", "joint_state", names=JOINTS)
    rec.add_provider(
        "icub/skin/torso", "float_array", dtype="float64", shape=[48], baseline=SKIN_BASELINE
    )
    rec.add_provider("icub/cam/left", "image", encoding="rgb8")
    rec.add_provider("kinect/depth", "image", encoding="32FC1")
    rec.add_provider("icub/mic", "audio", sample_rate=16000, channels=2)
    rec.add_provider("icub/speech", "string")
    rec.add_provider("icub/force", "float_array", dtype="float32")
    return rec


def make_samples(rng: np.random.Generator, i: int) -> dict[str, Any]:
    """The samples of tick ``i``: every third tick the skin is touched, else at baseline."""
    skin = np.full(48, SKIN_BASELINE)
    if i % 3 == 0:
        skin[rng.integers(0, 48, 3)] = rng.uniform(6, 200, 3)
    depth = rng.uniform(0.3, 4.0, (6, 8)).astype(np.float32)
    depth[0, 0] = np.nan  # no reading: NaN must survive bit for bit
    return {
        "icub/head": {
            "position": rng.normal(size=4),
            "velocity": rng.normal(size=4),
        },
        "icub/skin/torso": skin,
        "icub/cam/left": rng.integers(0, 256, (6, 8, 3), dtype=np.uint8),
        "kinect/depth": depth,
        "icub/mic": rng.integers(-30000, 30000, (160, 2)).astype(np.int16),
        "icub/speech": f"tick {i}: héllo",
        "icub/force": rng.normal(size=(2, 3)).astype(np.float32),
    }


def assert_same(name: str, got: Any, sent: Any) -> None:
    """Bit-exact equality of a replayed value and the sample sent."""
    if isinstance(sent, str):
        assert got == sent, name
    elif isinstance(sent, dict):
        for key, part in sent.items():
            assert_same(f"{name}.{key}", got[key], part)
    else:
        sent = np.asarray(sent)
        assert got.dtype == sent.dtype and got.shape == sent.shape, name
        assert got.tobytes() == sent.tobytes(), name


@pytest.fixture
def recorded(tmp_path: Path) -> tuple[Path, list[dict[str, Any]], list[int]]:
    """A closed recording of 30 ticks, the samples sent and their tick times."""
    rng = np.random.default_rng(7)
    rec = make_recorder(tmp_path / "ep-1")
    sent, times = [], []
    for i in range(30):
        samples = make_samples(rng, i)
        result = rec.tick(samples, time_ns=1_700_000_000_000_000_000 + i * 10_000_000)
        sent.append(samples)
        times.append(result.time_ns)
    rec.close()
    return tmp_path / "ep-1", sent, times


RecorderFactory = Callable[..., Recorder]


@pytest.fixture
def new_recorder() -> Callable[..., Recorder]:
    """``make_recorder``: a recorder with one provider of each kind."""
    return make_recorder


@pytest.fixture
def samples_for() -> Callable[[np.random.Generator, int], dict[str, Any]]:
    """``make_samples``: the samples of one tick."""
    return make_samples


@pytest.fixture
def same() -> Callable[[str, Any, Any], None]:
    """``assert_same``: bit-exact comparison of a replayed and a sent value."""
    return assert_same
