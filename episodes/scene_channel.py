"""An episode's stored scenes as a Foxglove ``SceneUpdate`` channel inside its own MCAP file.

When an episode ends, the experienced scenes linked to it (``engram:happenedDuring``) are read
from the episodic graph with their primitives (:func:`kg.scene_triples.read_scene`, the reader
the views use too) and written into the episode's rosbag2 recording
``<data_dir>/streams/<id>/`` as the ``/engram/scenes`` channel (``foxglove_msgs/msg/SceneUpdate``,
CDR; see :mod:`episodes.streams.foxglove`), one message per scene at the time it was stored. An
episode that recorded no streams gets a recording holding only its scenes.
"""

import datetime as dt
import logging
from pathlib import Path

from pyoxigraph import Literal, NamedNode

from episodes.streams.errors import CorruptRecordingError
from episodes.streams.foxglove import add_scene_channel, scene_entity, scene_message
from episodes.streams.registry import bag_path
from episodes.terms import check_id, episode_iri
from kg import Store
from kg.scene_triples import read_scene
from ontologies.vocab import (
    CREATED,
    EPISODIC,
    HAPPENED_DURING,
)

__all__ = ["scene_bag_path", "write_episode_scenes"]

log = logging.getLogger(__name__)


def scene_bag_path(data_dir: Path, episode_id: str) -> Path:
    """The rosbag2 directory that receives the episode's scene channel: its recording."""
    return bag_path(data_dir / "streams", check_id(episode_id, "episode"))


def write_episode_scenes(store: Store, data_dir: Path, episode_id: str) -> Path | None:
    """Write the episode's scenes as a ``SceneUpdate`` channel into its recording's MCAP file
    and return that file; None when it has no scenes, or when the recording cannot be read
    (logged: the episode still ends, its recording untouched)."""
    episode = episode_iri(episode_id)
    updates = []
    for quad in store.quads(None, HAPPENED_DURING, episode, EPISODIC):
        scene = quad.subject
        if not isinstance(scene, NamedNode):
            continue
        created = next(store.quads(scene, CREATED, None, EPISODIC), None)
        if created is None or not isinstance(created.object, Literal):
            continue
        time_ns = int(dt.datetime.fromisoformat(created.object.value).timestamp() * 1e9)
        primitives = [primitive for _, primitive in read_scene(store, scene, EPISODIC)]
        name = scene.value.rsplit("#", 1)[-1]
        updates.append((time_ns, scene_message(scene_entity(name, primitives, time_ns=time_ns))))
    if not updates:
        return None
    try:
        path = add_scene_channel(
            scene_bag_path(data_dir, episode_id), updates, episode_id=episode_id
        )
    except CorruptRecordingError as error:
        log.warning("episode %s: scenes not written into its recording: %s", episode_id, error)
        return None
    log.info("episode %s: %d scenes written to %s", episode_id, len(updates), path)
    return path
