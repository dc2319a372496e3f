"""Stream descriptors: the RDF side of the recorded streams.

When an episode ends, the stream recorder (``episodes.streams``) reports one ``ChannelStats``
per channel; :func:`descriptors_from_stats` turns them into :class:`StreamDescriptor` records and
:func:`write_descriptors` stores them in the ``episodes`` graph (``prov:wasGeneratedBy`` the
episode). This module reads the stats by attribute and does not import the recorder.
"""

from collections.abc import Iterable
from pathlib import Path
from typing import Any

from pyoxigraph import Literal, NamedNode

from episodes import _rdf
from episodes.model import StreamDescriptor
from episodes.terms import part_iri
from episodes.times import from_ns, to_literal
from kg import Store, Transaction
from ontologies.vocab import (
    DROPPED_COUNT,
    EPISODES,
    FIRST_SAMPLE_TIME,
    LAST_SAMPLE_TIME,
    MESSAGE_TYPE,
    PROV_WAS_GENERATED_BY,
    RDF_TYPE,
    SAMPLE_COUNT,
    STREAM_CHANNEL,
    STREAM_DESCRIPTOR,
    STREAM_FILE,
    STREAM_PROVIDER,
)

__all__ = [
    "descriptors_from_recording",
    "descriptors_from_stats",
    "read_descriptors",
    "write_descriptors",
]


def descriptors_from_stats(stats: Iterable[Any], root: Path) -> list[StreamDescriptor]:
    """Descriptors from the recorder's ``ChannelStats``; files are stored relative to ``root``."""
    descriptors = []
    for channel in stats:
        path = Path(channel.path)
        try:
            file = path.relative_to(root).as_posix()
        except ValueError:
            file = path.as_posix()
        descriptors.append(
            StreamDescriptor(
                provider=str(channel.provider),
                channel=str(channel.channel),
                message_type=str(channel.message_type),
                count=int(channel.count_stored),
                dropped=int(channel.count_dropped),
                file=file,
                first_time=from_ns(channel.first_time_ns),
                last_time=from_ns(channel.last_time_ns),
            )
        )
    return descriptors


def descriptors_from_recording(replayer: Any, root: Path) -> list[StreamDescriptor]:
    """Descriptors read from a finished recording (an ``episodes.streams.Replayer``), for an
    episode whose recording was closed before the episode ended. The file does not say how
    many samples were dropped, so ``dropped`` is ``None`` (unknown), never a made-up zero."""
    first: dict[str, int] = {}
    last: dict[str, int] = {}
    for tick in replayer.ticks:
        for provider in tick.providers:  # baseline samples count: they were received
            first.setdefault(provider, tick.time_ns)
            last[provider] = tick.time_ns
    path = Path(replayer.path)
    try:
        file = path.relative_to(root).as_posix()
    except ValueError:
        file = path.as_posix()
    counts = replayer.counts()
    return [
        StreamDescriptor(
            provider=name,
            channel=str(spec.topic),
            message_type=str(spec.msgtype),
            count=int(counts.get(name, 0)),
            dropped=None,
            file=file,
            first_time=from_ns(first.get(name)),
            last_time=from_ns(last.get(name)),
        )
        for name, spec in replayer.providers.items()
    ]


def write_descriptors(
    tx: Transaction, episode: NamedNode, descriptors: Iterable[StreamDescriptor]
) -> None:
    """Queue the descriptors of an episode's streams in ``tx``."""
    for d in descriptors:
        node = part_iri(episode, "stream", d.channel.strip("/") or "root")
        tx.insert(node, RDF_TYPE, STREAM_DESCRIPTOR, EPISODES)
        tx.insert(node, PROV_WAS_GENERATED_BY, episode, EPISODES)
        tx.insert(node, STREAM_PROVIDER, Literal(d.provider), EPISODES)
        tx.insert(node, STREAM_CHANNEL, Literal(d.channel), EPISODES)
        tx.insert(node, MESSAGE_TYPE, Literal(d.message_type), EPISODES)
        tx.insert(node, SAMPLE_COUNT, Literal(d.count), EPISODES)
        if d.dropped is not None:
            tx.insert(node, DROPPED_COUNT, Literal(d.dropped), EPISODES)
        tx.insert(node, STREAM_FILE, Literal(d.file), EPISODES)
        if d.first_time is not None:
            tx.insert(node, FIRST_SAMPLE_TIME, to_literal(d.first_time), EPISODES)
        if d.last_time is not None:
            tx.insert(node, LAST_SAMPLE_TIME, to_literal(d.last_time), EPISODES)


def read_descriptors(store: Store, episode: NamedNode) -> tuple[StreamDescriptor, ...]:
    """The stream descriptors of an episode, by channel."""
    return tuple(
        StreamDescriptor(
            provider=_rdf.text(r, "provider"),
            channel=_rdf.text(r, "channel"),
            message_type=_rdf.text(r, "type"),
            count=_rdf.integer(r, "count"),
            dropped=_rdf.integer(r, "dropped") if "dropped" in r else None,
            file=_rdf.text(r, "file"),
            first_time=_rdf.opt_time(r, "first"),
            last_time=_rdf.opt_time(r, "last"),
        )
        for r in store.select("episodes_streams", episode=episode)
    )
