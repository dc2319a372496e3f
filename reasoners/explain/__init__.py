"""Explanations of the scene memory's decisions, derived on demand and rendered in words.

Nothing here writes. Each explanation is a frozen dataclass (its fields are the structured
answer, :func:`to_jsonable` turns it into JSON) with a ``words`` property saying it as a
sentence. They are derived from the live memory (its public read-only views) and, for what is
no longer live, from the ``trash`` and ``episodic`` graphs through ``sparql/explain_*.rq``:

- :class:`RecognitionExplanation`: an experienced scene stored under a class it belonged to:
  which restrictions of the class the scene met, what the scene had beyond them, the confidence
  arithmetic d(class)/d(scene) against the learn threshold, and the nearest classes it missed.
- :class:`LearningExplanation`: why a class was learned: no class learned before it fitted the
  scene well enough (the best confidence against the threshold), and the near misses.
- :class:`PlacementExplanation`: which restrictions make a class a subclass of each parent.
- :class:`LevelExplanation`: the score terms now, the level they give, the consecutive WEAK
  passes, the grace period and pins, and whether the next sleep pass would forget it.
- :class:`ForgettingExplanation` and :class:`RestoreExplanation`: why something is in the
  trash, and whether (and with what) it can come back.

A learning explanation names the best class and confidence recorded when the class was learned
(PROV triples in the history graph, :mod:`reasoners.history`), even a class forgotten since;
without a record (a store older than its history) it compares the class with the classes learned
before it that are still live.

>>> import datetime as dt
>>> from kg import Store
>>> from reasoners.memory import SceneMemory
>>> from kg.primitive import Primitive
>>> memory = SceneMemory(Store(), clock=lambda: dt.datetime(2025, 1, 1, tzinfo=dt.UTC))
>>> ball = Primitive("ball", "Sphere", centre=(.3, .3, .3), radius=.05)
>>> table = Primitive("table", "Plane", centre=(.3, .1, .1), axis=(0, 0, 1))
>>> stored = memory.store_scene([ball, table])
>>> print(explain_learning(memory, stored.stored_as).words)  # doctest: +NORMALIZE_WHITESPACE
I learned Scene-1 because no class I knew before it fitted its scene: I knew none.
"""

from reasoners.explain.derive import (
    explain,
    explain_forgetting,
    explain_learning,
    explain_level,
    explain_placement,
    explain_scene,
    explain_subsumption,
    scene_signature,
)
from reasoners.explain.kinds import (
    Explanation,
    ForgettingExplanation,
    LearningExplanation,
    LevelExplanation,
    NearMiss,
    ParentLink,
    PlacementExplanation,
    RecognitionExplanation,
    RestoreExplanation,
    RestrictionCheck,
    to_jsonable,
)

__all__ = [
    "Explanation",
    "ForgettingExplanation",
    "LearningExplanation",
    "LevelExplanation",
    "NearMiss",
    "ParentLink",
    "PlacementExplanation",
    "RecognitionExplanation",
    "RestoreExplanation",
    "RestrictionCheck",
    "explain",
    "explain_forgetting",
    "explain_learning",
    "explain_level",
    "explain_placement",
    "explain_scene",
    "explain_subsumption",
    "scene_signature",
    "to_jsonable",
]
