"""An episode's stored scenes as a Foxglove ``SceneUpdate`` channel, one MCAP file per episode.

When an episode ends, the experienced scenes linked to it (``engram:happenedDuring``) are read
from the episodic graph with their primitives and written to ``<data_dir>/scenes/<id>.mcap``
(see :mod:`episodes.streams.foxglove` for the format and why it is a file of its own), one
message per scene at the time it was stored.
"""

import datetime as dt
import logging
from pathlib import Path
from typing import Any

from pyoxigraph import Literal, NamedNode

from episodes.streams.foxglove import scene_entity, scene_update, write_scene_mcap
from episodes.terms import check_id, episode_iri
from kg import Store
from ontologies.vocab import (
    AXIS,
    CENTRE,
    COLOUR,
    CREATED,
    ENGRAM_NS,
    EPISODIC,
    HAPPENED_DURING,
    HAS_PRIMITIVE,
    HEIGHT,
    RADIUS,
    RDF_TYPE,
    RDFS_LABEL,
)

__all__ = ["scene_mcap_path", "write_episode_scenes"]

log = logging.getLogger(__name__)
_KINDS = {ENGRAM_NS + k: k for k in ("Sphere", "Cylinder", "Cone", "Plane")}


def scene_mcap_path(data_dir: Path, episode_id: str) -> Path:
    """Where the scene channel of an episode is written."""
    return data_dir / "scenes" / f"{check_id(episode_id, 'episode')}.mcap"


def _values(store: Store, subject: NamedNode) -> dict[str, Any]:
    out: dict[str, Any] = {}
    for quad in store.quads(subject, None, None, EPISODIC):
        if quad.predicate == RDF_TYPE and isinstance(quad.object, NamedNode):
            out.setdefault("kind", _KINDS.get(quad.object.value))
        elif isinstance(quad.object, Literal):
            out.setdefault(quad.predicate.value, quad.object.value)
    return out


def _primitive(store: Store, iri: NamedNode) -> dict[str, Any] | None:
    values = _values(store, iri)

    def vector(props: tuple[NamedNode, ...]) -> tuple[float, ...] | None:
        if not all(p.value in values for p in props):
            return None
        return tuple(float(values[p.value]) for p in props)

    centre = vector(CENTRE)
    if values.get("kind") is None or centre is None:
        return None
    return {
        "id": values.get(RDFS_LABEL.value, iri.value.rsplit("#", 1)[-1]),
        "kind": values["kind"],
        "centre": centre,
        "axis": vector(AXIS),
        "radius": float(values[RADIUS.value]) if RADIUS.value in values else None,
        "height": float(values[HEIGHT.value]) if HEIGHT.value in values else None,
        "colour": vector(COLOUR),
    }


def write_episode_scenes(store: Store, data_dir: Path, episode_id: str) -> Path | None:
    """Write the episode's scenes as a ``foxglove.SceneUpdate`` channel; None when it has none."""
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
        members = [
            q.object
            for q in store.quads(scene, HAS_PRIMITIVE, None, EPISODIC)
            if isinstance(q.object, NamedNode)
        ]
        members.sort(key=lambda m: (len(m.value), m.value))
        primitives = [p for m in members if (p := _primitive(store, m)) is not None]
        name = scene.value.rsplit("#", 1)[-1]
        updates.append((time_ns, scene_update(scene_entity(name, primitives, time_ns=time_ns))))
    if not updates:
        return None
    path = write_scene_mcap(scene_mcap_path(data_dir, episode_id), updates)
    log.info("episode %s: %d scenes written to %s", episode_id, len(updates), path)
    return path
