"""Derived streams beside their originals: replay merged by frame, and export as own topics.

An augmentation run's stream file (written by the episode memory) holds each derived sample
stamped with the tick time of the recorded frame it was computed from. Here those stamps are
matched to the source's frames: :func:`derived_frames` replays a run alone, numbered by source
frame; :func:`merged_frames` adds the runs' samples to the source frames they came from, under
prefixed names (``augmentations/edges/v2/left/edges``); :func:`export_merged` writes the episode
and its runs as one rosbag2 bag, each derived channel its own topic.
"""

from __future__ import annotations

import re
from collections import defaultdict
from collections.abc import Collection, Iterator, Sequence
from dataclasses import replace
from pathlib import Path

from episodes.streams.bagio import _BACKLOG_BYTES, _settings, _tick
from episodes.streams.errors import RecordingStateError
from episodes.streams.ledger import ChannelStats
from episodes.streams.mcapread import LIMIT_BYTES
from episodes.streams.recorder import Recorder
from episodes.streams.replay import Frame, Replayer, Sample

__all__ = ["derived_frames", "export_merged", "merged_frames", "run_prefix"]


def run_prefix(name: str, version: int) -> str:
    """The name prefix of a run's channels beside the originals: ``augmentations/<name>/v<n>``."""
    safe = re.sub(r"[^A-Za-z0-9_]+", "_", name).strip("_") or "run"
    if safe[0].isdigit():
        safe = "a_" + safe
    return f"augmentations/{safe}/v{version}"


def _frame_of(source: Replayer) -> dict[int, int]:
    return {tick.time_ns: tick.frame for tick in source.ticks}


def derived_frames(
    source: Replayer, run: Replayer, channels: Collection[str] | None = None
) -> Iterator[Frame]:
    """The run's samples alone, each frame numbered and timed as the source frame it comes
    from (samples whose source time is unknown keep the run's own numbering)."""
    frames = _frame_of(source)
    for frame in run.frames(channels):
        stamp = next(iter(frame.samples.values())).stamp_ns
        number = frames.get(stamp)
        if number is None:
            yield frame
            continue
        yield Frame(
            number,
            stamp,
            {k: replace(s, frame=number, time_ns=stamp) for k, s in frame.samples.items()},
        )


def _by_source_time(prefix: str, run: Replayer) -> dict[int, dict[str, Sample]]:
    found: dict[int, dict[str, Sample]] = defaultdict(dict)
    for frame in run.frames():
        for name, sample in frame.samples.items():
            label = f"{prefix}/{name}"
            found[sample.stamp_ns][label] = replace(
                sample, provider=label, channel="/" + label, time_ns=sample.stamp_ns
            )
    return found


def merged_frames(
    source: Replayer,
    runs: Sequence[tuple[str, Replayer]],
    channels: Collection[str] | None = None,
) -> Iterator[Frame]:
    """The source's frames (``channels`` of it, or all), each with the samples the runs derived
    from it, named ``<prefix>/<derived channel>``. ``runs``: (prefix, run replayer) pairs."""
    derived: dict[int, dict[str, Sample]] = defaultdict(dict)
    for prefix, run in runs:
        for time_ns, samples in _by_source_time(prefix, run).items():
            derived[time_ns].update(samples)
    for frame in source.frames(channels):
        extra = {
            name: replace(sample, frame=frame.number)
            for name, sample in derived.get(frame.time_ns, {}).items()
        }
        yield Frame(frame.number, frame.time_ns, {**frame.samples, **extra})


def export_merged(
    source: Path | str,
    runs: Sequence[tuple[str, Path]],
    dest: Path | str,
    *,
    limit_bytes: int = LIMIT_BYTES,
) -> list[ChannelStats]:
    """Write the episode at ``source`` and its runs as one standalone rosbag2 directory: the
    original topics, and each derived channel as ``/<prefix>/<channel>``; each record and
    decompressed chunk read may take at most ``limit_bytes``.

    Raises:
        RecordingStateError: ``dest`` exists already.
    """
    dest = Path(dest)
    if dest.exists():
        raise RecordingStateError(f"dest: {str(dest)!r} exists already")
    original = Replayer(source, limit_bytes=limit_bytes)
    replayers = [(prefix, Replayer(path, limit_bytes=limit_bytes)) for prefix, path in runs]
    recorder = Recorder(dest, episode_id=original.episode_id, max_queue_bytes=4 * _BACKLOG_BYTES)
    try:
        for name, spec in original.providers.items():
            recorder.add_provider(name, spec.kind, **_settings(spec, keep_baseline=False))
        for prefix, run in replayers:
            for name, spec in run.providers.items():
                recorder.add_provider(
                    f"{prefix}/{name}", spec.kind, **_settings(spec, keep_baseline=False)
                )
        for frame in merged_frames(original, replayers):
            _tick(recorder, frame)
    except BaseException:
        recorder.close()
        raise
    return recorder.close()
