"""The perception client (the seed's VisClient): stable scenes from ``shapes`` into the memory.

Each stable scene that :class:`shapes.Perception` reports becomes one directive list, ``LOAD
INIT``, an ``ADD IND CLASS`` and ``ADD DATAPROP IND`` per primitive, ``SCENE UPDATED``, sent as
one transaction through an :class:`~api.client.ArmorClient` (over HTTP, or in this process with
:class:`~api.client.LocalTransport`).
"""

from collections.abc import Iterable, Iterator
from dataclasses import dataclass
from enum import IntEnum

from api.client import ArmorClient, MemoryAnswer, ScenePrimitive
from shapes import Frame, Perception, Primitive, StableScene

__all__ = ["PerceiveExit", "PerceivedScene", "exit_status", "perceive", "scene_primitives"]


class PerceiveExit(IntEnum):
    """The exit status of ``engram perceive`` (docs/perception.md), whether the memory is
    local or reached over HTTP and whether the source is a file or a bag."""

    STORED = 0
    """At least one scene was stored."""
    MEMORY_ERROR = 1
    """The memory refused a scene or could not be reached (nothing more was stored)."""
    BAD_INPUT = 2
    """The source or an option is invalid: missing, malformed, not a cloud, a bad pose."""
    NOTHING_STORED = 3
    """The source was read but gave no scene to store; the output says why."""


def exit_status(stored: int) -> PerceiveExit:
    """The exit status of a run that read its whole source and stored ``stored`` scenes.

    >>> exit_status(2).name, exit_status(0).name
    ('STORED', 'NOTHING_STORED')
    """
    return PerceiveExit.STORED if stored > 0 else PerceiveExit.NOTHING_STORED


@dataclass(frozen=True)
class PerceivedScene:
    """One stable scene and what the memory made of it."""

    scene: StableScene
    answer: MemoryAnswer

    @property
    def stored_as(self) -> str:
        """The class the scene was stored under (learned or reinforced)."""
        return self.answer.values[0] if self.answer.values else ""

    @property
    def learned(self) -> bool:
        return self.answer.details.get("learned") == ["true"]


def _name(primitive: Primitive, position: int) -> str:
    kind = primitive.kind.value.lower()
    ident = primitive.tracking_id if primitive.tracking_id is not None else position
    return f"{kind}{ident}"


def scene_primitives(scene: StableScene) -> list[ScenePrimitive]:
    """The scene's averaged primitives as the memory client sends them: its objects, then
    the supports they stand on (Planes), so one mug on a table is a scene of two.

    >>> from shapes import ShapeKind, StableScene
    >>> ball = Primitive(ShapeKind.SPHERE, centre=(0.1, 0.2, 0.05), radius=0.05, tracking_id=3)
    >>> [p.name for p in scene_primitives(StableScene(0, None, (ball,), {}, 5))]
    ['sphere3']
    """
    return [
        ScenePrimitive(
            name=_name(p, position),
            kind=p.kind.value,
            centre=p.centre,
            axis=p.axis,
            radius=p.radius,
            height=p.height,
            apex=p.apex,
            point_on_axis=p.point_on_axis,
            hessian=p.hessian_offset,
            colour=p.colour,
            tracking_id=p.tracking_id,
            extent_x=None if p.extent is None else p.extent[0],
            extent_y=None if p.extent is None else p.extent[1],
        )
        for position, p in enumerate(scene.primitives + scene.supports)
    ]


def perceive(
    frames: Iterable[Frame],
    client: ArmorClient,
    *,
    perception: Perception | None = None,
    episode: str | None = None,
    finish: bool = True,
) -> Iterator[PerceivedScene]:
    """Run perception over ``frames`` and store every stable scene; yield what was stored.

    ``finish``: ``frames`` is a finite source (a file, a bag); at its end the scene it has is
    stored too, marked with the frames it averages, even if it never held still long enough
    (so one scan stores one scene). When nothing is stored, ``perception.why_no_scene()`` says
    why.

    Raises :class:`~api.client.ArmorServiceInternalError` when the memory refuses a scene (the
    scene's list then changed nothing) and the errors of ``shapes`` for bad frames.
    """
    perception = perception or Perception()
    for scene in perception.stable_scenes(frames, finish=finish):
        if not scene.primitives:
            continue
        answer = client.memory.store_scene(scene_primitives(scene), episode=episode)
        yield PerceivedScene(scene, answer)
