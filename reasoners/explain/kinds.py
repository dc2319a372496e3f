"""What an explanation holds (frozen dataclasses, JSON through :func:`to_jsonable`) and how
it says it (each kind's ``words``)."""

import dataclasses
import datetime as dt
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

from reasoners.labels import RELATION_WORDS, local
from reasoners.scoring import WEAK
from reasoners.signature import Signature

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
    "beyond",
    "checks",
    "to_jsonable",
]

_KINDS = ("sphere", "cylinder", "cone", "plane")


def _times(n: int) -> str:
    return {0: "never", 1: "once", 2: "twice"}.get(n, f"{n} times")


def _say_count(n: int, noun: str) -> str:
    return f"{n} {noun}{'' if n == 1 else 's'}"


@dataclass(frozen=True)
class RestrictionCheck:
    """One restriction ``≥required property.type`` and how many objects a scene had for it."""

    prop: str
    leaf: str
    required: int
    found: int

    @property
    def met(self) -> bool:
        return self.found >= self.required

    def _phrase(self) -> str:
        name = self.prop
        kind = next((k for k in _KINDS if name.lower().startswith(k)), "")
        rest = name[len(kind) :]
        relation = RELATION_WORDS.get(rest[:1].lower() + rest[1:], rest)
        return f"a {kind} {relation}" if kind else relation

    @property
    def words(self) -> str:
        """The restriction: "a sphere above at least 1 plane" for sphereIsAboveOf ≥1 Plane."""
        return f"{self._phrase()} at least {_say_count(self.required, self.leaf.lower())}"

    @property
    def extra_words(self) -> str:
        """For a part beyond a class (``required`` more than the class asks, ``found`` in all):
        "a plane below 2 spheres (1 more)"."""
        leaf = self.leaf.lower()
        if self.found == self.required:
            return f"{self._phrase()} {_say_count(self.found, leaf)}"
        return f"{self._phrase()} {_say_count(self.found, leaf)} ({self.required} more)"


def checks(required: Signature, found: Signature) -> tuple[RestrictionCheck, ...]:
    """Each restriction of ``required`` with how many objects ``found`` has for it."""
    return tuple(
        RestrictionCheck(local(p), local(t), n, found.get((p, t), 0))
        for (p, t), n in required.items()
    )


def beyond(signature: Signature, cls: Signature) -> tuple[RestrictionCheck, ...]:
    """What ``signature`` has beyond ``cls``: each key with the part of its count ``cls`` does
    not ask for (``required`` is that part, ``found`` the whole count)."""
    extra = []
    for (p, t), n in signature.items():
        asked = cls.get((p, t), 0)
        if n > asked:
            extra.append(RestrictionCheck(local(p), local(t), n - asked, n))
    return tuple(extra)


def _list(checks: Sequence[RestrictionCheck], *, found: bool = True) -> str:
    parts = [f"{c.words} (it had {c.found})" if found else c.extra_words for c in checks]
    return "; ".join(parts) if parts else "nothing"


@dataclass(frozen=True)
class NearMiss:
    """A class a scene did not belong to, how similar they were, and the restrictions it missed."""

    cls: str
    similarity: float
    missed: tuple[RestrictionCheck, ...]

    @property
    def words(self) -> str:
        return f"{local(self.cls)} (similarity {self.similarity:.2f}) asks for " + _list(
            self.missed
        )


@dataclass(frozen=True)
class RecognitionExplanation:
    """Why an experienced scene was stored under a class it belonged to."""

    kind = "recognition"
    scene: str
    stored_as: str
    scene_complexity: int
    class_complexity: int
    confidence: float
    threshold: float
    met: tuple[RestrictionCheck, ...]
    beyond: tuple[RestrictionCheck, ...]
    """What the scene had that the class does not ask for."""
    near_misses: tuple[NearMiss, ...]

    @property
    def words(self) -> str:
        scene, cls = local(self.scene), local(self.stored_as)
        text = (
            f"I recognised {scene} as {cls}: it met all {_say_count(len(self.met), 'restriction')}"
            f" of {cls}: {_list(self.met)}. Confidence = d({cls}) / d(scene) = "
            f"{self.class_complexity}/{self.scene_complexity} = {self.confidence:.2f}, "
            f"at least the learn threshold {self.threshold:g}, so I reinforced {cls}."
        )
        if self.beyond:
            text += f" Beyond {cls} the scene had {_list(self.beyond, found=False)}."
        return text


@dataclass(frozen=True)
class LearningExplanation:
    """Why a class was learned: no class learned before it fitted its scene well enough."""

    kind = "learning"
    cls: str
    scene: str | None
    """The experienced scene it was learned from, when known."""
    complexity: int
    best: str | None
    """The most confident class learned before it that the scene belonged to."""
    best_complexity: int
    best_confidence: float
    threshold: float
    recognised: tuple[tuple[str, float], ...]
    """Every earlier class the scene belonged to, with its confidence."""
    near_misses: tuple[NearMiss, ...]
    recorded: bool = False
    """Whether the best class and its confidence are those recorded when the class was learned
    (the history's PROV triples), rather than derived from the classes live now."""

    @property
    def words(self) -> str:
        cls = local(self.cls)
        if self.best is None:
            text = f"I learned {cls} because no class I knew before it fitted its scene"
            if not self.near_misses:
                return text + ": I knew none."
            return (
                text
                + ": its scene belonged to none of them. The closest: "
                + "; ".join(m.words for m in self.near_misses)
                + "."
            )
        best = local(self.best)
        text = (
            f"I learned {cls} because the best class I knew, {best}, fitted its scene with "
            f"confidence d({best}) / d(scene) = {self.best_complexity}/{self.complexity} = "
            f"{self.best_confidence:.2f}, below the learn threshold {self.threshold:g}."
        )
        if self.near_misses:
            text += " Closer classes missed: " + "; ".join(m.words for m in self.near_misses) + "."
        return text


@dataclass(frozen=True)
class ParentLink:
    """A direct parent and the restrictions of it that the child meets."""

    parent: str
    restrictions: tuple[RestrictionCheck, ...]
    adds: tuple[RestrictionCheck, ...]
    """What the child asks for beyond the parent."""


@dataclass(frozen=True)
class PlacementExplanation:
    """Why a class sits where it does in the graph: which restrictions make it a subclass of
    each direct parent (or of a chosen ancestor), or which it lacks."""

    kind = "placement"
    cls: str
    parents: tuple[ParentLink, ...]
    missed: tuple[RestrictionCheck, ...] = ()
    """With :func:`explain_subsumption` for a class it is not a kind of: what it lacks."""
    asked: str | None = None
    """With :func:`explain_subsumption`: the class asked about."""

    @property
    def is_kind(self) -> bool:
        return not self.missed

    @property
    def words(self) -> str:
        cls = local(self.cls)
        if self.asked is not None and self.missed:
            return (
                f"{cls} is not a kind of {local(self.asked)}: {local(self.asked)} asks for "
                f"{_list(self.missed)}."
            )
        if not self.parents:
            return f"{cls} is directly under Scene: no class I know is more general than it."
        parts = []
        for link in self.parents:
            part = (
                f"{cls} is a kind of {local(link.parent)} because it meets every restriction "
                f"of {local(link.parent)}: {_list(link.restrictions)}"
            )
            if link.adds:
                part += f"; it adds {_list(link.adds, found=False)}"
            parts.append(part)
        return ". ".join(parts) + "."


@dataclass(frozen=True)
class LevelExplanation:
    """A live class's or experienced scene's score terms now, its level and its fate."""

    kind = "level"
    about: str
    item_kind: str
    """"class" or "item"."""
    terms: dict[str, float]
    """Each weighted term of ζ (for an item, ``decay`` is subtracted)."""
    zeta: float
    normalised: float
    level: str
    high_threshold: float
    weak_threshold: float
    consecutive_weak: int
    passes_to_forget: int
    age_s: float
    grace_s: float
    pinned: bool
    protected_by: tuple[str, ...]
    """Pinned experienced scenes that keep this class."""

    @property
    def next_pass_forgets(self) -> bool:
        """Whether the next sleep pass forgets it if its level stays what it is now."""
        return (
            self.level == WEAK
            and self.consecutive_weak + 1 >= self.passes_to_forget
            and self.age_s >= self.grace_s
            and not self.pinned
            and not self.protected_by
        )

    @property
    def words(self) -> str:
        name = local(self.about)
        terms = " + ".join(f"{k} {v:.3f}" for k, v in self.terms.items() if k != "decay")
        if "decay" in self.terms:
            terms += f" - decay {self.terms['decay']:.3f}"
        text = (
            f"{name}'s score is {terms} = {self.zeta:.3f}, {self.normalised:.2f} of the best, "
            f"so its level is {self.level} (HIGH above {self.high_threshold:g}, WEAK below "
            f"{self.weak_threshold:g}). It was WEAK at {self.consecutive_weak} consecutive "
            f"sleep pass{'' if self.consecutive_weak == 1 else 'es'}; I forget after "
            f"{self.passes_to_forget}"
        )
        if self.pinned:
            return text + ", but it is pinned, so I keep it."
        if self.protected_by:
            return text + f", but the pinned scene {local(self.protected_by[0])} keeps it."
        if self.age_s < self.grace_s:
            return text + (
                f", but it is {self.age_s / 3600:.1f} h old, within the grace period of "
                f"{self.grace_s / 3600:.1f} h."
            )
        if self.next_pass_forgets:
            return text + ", so the next sleep pass forgets it if it is still WEAK."
        return text + "."


@dataclass(frozen=True)
class RestoreExplanation:
    """Whether a trashed class or scene can be restored, and what would come back with it."""

    kind = "restore"
    about: str
    restorable: bool
    reason: str
    brings_back: tuple[str, ...]

    @property
    def words(self) -> str:
        name = local(self.about)
        if not self.restorable:
            return f"I cannot restore {name}: {self.reason}."
        more = ""
        if self.brings_back:
            more = " with " + ", ".join(local(i) for i in self.brings_back)
        return f"I can restore {name}{more}, exactly as it was ({self.reason})."


@dataclass(frozen=True)
class ForgettingExplanation:
    """Why a class or experienced scene is in the trash, from the values it had then."""

    kind = "forgetting"
    about: str
    item_kind: str
    forgotten_at: dt.datetime
    created: dt.datetime | None
    weak_passes: int
    """Consecutive WEAK passes at the pass that forgot it (the stored count plus that pass)."""
    passes_to_forget: int
    grace_s: float
    pinned: bool
    score: float | None
    store_count: int | None
    retrieve_count: int | None
    with_class: str | None
    """For a scene forgotten with its class: that class."""
    restore: RestoreExplanation

    @property
    def words(self) -> str:
        name = local(self.about)
        when = self.forgotten_at.isoformat(timespec="seconds")
        if self.with_class is not None:
            text = f"I forgot {name} at {when} together with its class {local(self.with_class)}."
        else:
            age = ""
            if self.created is not None:
                hours = (self.forgotten_at - self.created).total_seconds() / 3600
                age = (
                    f", it was {hours:.1f} h old (the grace period is {self.grace_s / 3600:.1f} h)"
                )
            counts = ""
            if self.store_count is not None:
                counts = f"; it had been stored {_times(self.store_count)} and " + (
                    f"retrieved {_times(self.retrieve_count)}"
                    if self.retrieve_count
                    else "never retrieved"
                )
            text = (
                f"I forgot {name} at {when} because its level was WEAK at "
                f"{self.weak_passes} consecutive sleep passes (I forget after "
                f"{self.passes_to_forget}){age}, and it was not pinned{counts}."
            )
        return text + " " + self.restore.words


Explanation = (
    RecognitionExplanation
    | LearningExplanation
    | PlacementExplanation
    | LevelExplanation
    | ForgettingExplanation
    | RestoreExplanation
)


def _plain(value: Any) -> Any:
    if isinstance(value, dt.datetime):
        return value.isoformat()
    if isinstance(value, dict):
        return {k: _plain(v) for k, v in value.items()}
    if isinstance(value, list | tuple):
        return [_plain(v) for v in value]
    return value


def _part(value: Any) -> dict[str, Any]:
    """A restriction check, near miss or parent link as JSON, with its words when it has some."""
    body = {
        spec.name: [_part(v) for v in item]
        if isinstance(item := getattr(value, spec.name), tuple)
        and item
        and dataclasses.is_dataclass(item[0])
        else _plain(item)
        for spec in dataclasses.fields(value)
    }
    if hasattr(value, "words"):
        body["words"] = value.words
    if hasattr(value, "met"):
        body["met"] = value.met
    return body


def to_jsonable(explanation: Explanation) -> dict[str, Any]:
    """The explanation as JSON: its fields, its ``kind`` and its ``words``."""

    body: dict[str, Any] = {"kind": explanation.kind, "words": explanation.words}
    for spec in dataclasses.fields(explanation):
        value = getattr(explanation, spec.name)
        if isinstance(value, RestoreExplanation):
            body[spec.name] = to_jsonable(value)
        elif isinstance(value, tuple) and value and dataclasses.is_dataclass(value[0]):
            body[spec.name] = [_part(v) for v in value]
        else:
            body[spec.name] = _plain(value)
    return body
