"""The scene memory's operations as values, for :meth:`reasoners.memory.SceneMemory.commit`.

A caller that gathers several operations before it commits them with writes of its own (a
directive list of the ARMOR adapter) describes each as one of these values; the memory runs them
in order, in one transaction with the caller's writes, and returns one result per operation
(:data:`OperationResult`).

>>> from kg.primitive import Primitive
>>> StoreScene((Primitive("ball", "Sphere", centre=(.3, .3, .3), radius=.05),)).episode is None
True
"""

import datetime as dt
from collections.abc import Sequence
from dataclasses import dataclass

from pyoxigraph import NamedNode

from kg.primitive import Primitive
from reasoners.results import RetrievalResult, SleepReport, StoreResult
from reasoners.signature import Signature

__all__ = [
    "AdvanceClock",
    "Cue",
    "Operation",
    "OperationResult",
    "Pin",
    "Restore",
    "Retrieve",
    "SetClock",
    "Sleep",
    "StoreScene",
]


Cue = Signature | Sequence[Primitive] | Sequence[tuple[str, str, str]]
"""A partial scene: primitives, relation triples between object types such as
``("Sphere", "isAboveOf", "Plane")``, or a signature."""


@dataclass(frozen=True)
class StoreScene:
    """:meth:`~reasoners.memory.SceneMemory.store_scene`; its result is a StoreResult."""

    primitives: Sequence[Primitive]
    episode: NamedNode | None = None


@dataclass(frozen=True)
class Retrieve:
    """:meth:`~reasoners.memory.SceneMemory.retrieve`; its result is a RetrievalResult."""

    cue: Cue
    spread: bool = False


@dataclass(frozen=True)
class Sleep:
    """:meth:`~reasoners.memory.SceneMemory.sleep`; its result is a SleepReport."""


@dataclass(frozen=True)
class Pin:
    """:meth:`~reasoners.memory.SceneMemory.pin` (or unpin); its result is None."""

    iri: NamedNode
    pinned: bool = True


@dataclass(frozen=True)
class Restore:
    """:meth:`~reasoners.memory.SceneMemory.restore`; its result is the restored IRIs."""

    iri: NamedNode


@dataclass(frozen=True)
class SetClock:
    """Set the memory's settable clock to ``when``; its result is the clock's time after."""

    when: dt.datetime


@dataclass(frozen=True)
class AdvanceClock:
    """Move the memory's settable clock on by ``seconds``; its result is the clock's time after."""

    seconds: float


Operation = StoreScene | Retrieve | Sleep | Pin | Restore | SetClock | AdvanceClock
OperationResult = (
    StoreResult | RetrievalResult | SleepReport | tuple[NamedNode, ...] | dt.datetime | None
)
