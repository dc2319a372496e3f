"""Answers to questions in words, from the episodes, the scene memory and its explanations.

:meth:`Asker.ask` parses the question with :mod:`api.ask.grammar`, runs the form's answer and
returns an :class:`Answer`: the words, the structured answer, the explanations behind it and
the SPARQL it ran (each query as the store ran it, values bound). Scene questions recall from
the scene memory (:meth:`SceneMemory.retrieve`): as with any retrieval, what is recalled is
strengthened.
"""

import datetime as dt
import threading
from collections.abc import Callable, Iterator, Mapping
from contextlib import contextmanager
from dataclasses import dataclass, field
from typing import Any

from pyoxigraph import Literal, NamedNode

from api.ask.grammar import FORMS, Parsed, closest, parse, parse_thing
from api.ask.vocabulary import NameCache, time_window
from episodes import Cue, EpisodeMemory, say_when, to_jsonable
from episodes.errors import NotFoundError
from episodes.times import to_literal
from kg import Store
from kg.errors import InvalidValueError
from ontologies.vocab import TRASH, engram
from reasoners import history
from reasoners.errors import MemoryReasonerError
from reasoners.explain import (
    Explanation,
    LearningExplanation,
    RestrictionCheck,
    explain,
    explain_forgetting,
    explain_learning,
    explain_level,
    explain_scene,
    explain_subsumption,
)
from reasoners.explain import to_jsonable as explanation_json
from reasoners.labels import local
from reasoners.memory import SceneMemory

__all__ = ["Answer", "Asker"]

MAX_QUESTION = 500


@dataclass(frozen=True)
class Answer:
    """What :meth:`Asker.ask` says: words, the structured answer and how it was found."""

    question: str
    understood: bool
    words: str
    form: str | None = None
    slots: dict[str, str] = field(default_factory=dict)
    answer: dict[str, Any] = field(default_factory=dict)
    explanations: tuple[Explanation, ...] = ()
    sparql: tuple[str, ...] = ()
    suggestions: tuple[str, ...] = ()

    def to_json(self) -> dict[str, Any]:
        return {
            "question": self.question,
            "understood": self.understood,
            "words": self.words,
            "form": self.form,
            "slots": self.slots,
            "answer": self.answer,
            "explanations": [explanation_json(e) for e in self.explanations],
            "sparql": list(self.sparql),
            "suggestions": list(self.suggestions),
        }


@dataclass
class _Reply:
    words: str
    answer: dict[str, Any] = field(default_factory=dict)
    explanations: list[Explanation] = field(default_factory=list)


@contextmanager
def _queries(store: Store) -> Iterator[list[str]]:
    """The text of every query this thread runs on ``store`` inside the block."""
    ran: list[str] = []
    me = threading.get_ident()

    def tracer(kind: str, text: str, bindings: Mapping[str, Any]) -> None:
        if kind == "query" and threading.get_ident() == me:
            ran.append(text)

    with store.tracing(tracer):
        yield ran


def _iri(name: str) -> NamedNode:
    return engram(name)


def _describe(checks: tuple[RestrictionCheck, ...], limit: int = 3) -> str:
    words = [c.words for c in checks[:limit]]
    more = len(checks) - limit
    return ", ".join(words) + (f" and {more} more" if more > 0 else "")


class Asker:
    """Answers questions about ``scenes`` (the scene memory) and ``episodes``."""

    def __init__(self, scenes: SceneMemory, episodes: EpisodeMemory) -> None:
        self.scenes = scenes
        self.episodes = episodes
        self.store = scenes.store
        self.names = NameCache(episodes.store)
        self._answers: dict[str, Callable[[Parsed], _Reply]] = {
            "episode_when": self._episode_when,
            "episode_count": self._episode_count,
            "episode_between": self._episode_between,
            "episode_who": self._episode_who,
            "scene_know": self._scene_know,
            "scene_seen": self._scene_seen,
            "scene_best": self._scene_best,
            "scene_forgot": self._scene_forgot,
            "explain_last_scene": self._explain_last_scene,
            "explain_forget": self._explain_forget,
            "explain_kind": self._explain_kind,
            "explain_learn": self._explain_learn,
            "explain_level": self._explain_level,
            "explain_any": self._explain_any,
            "history_score": self._history_score,
            "history_as_of": self._history_as_of,
        }

    def ask(self, text: str) -> Answer:
        """Answer ``text``; a question outside the grammar gets the closest forms it knows.

        Raises :class:`~kg.errors.InvalidValueError` for text that is not a string, is empty or
        is longer than 500 characters.
        """
        if not isinstance(text, str) or not text.strip():
            raise InvalidValueError("text", text, "a question in words")
        if len(text) > MAX_QUESTION:
            raise InvalidValueError(
                "text", text[:40] + "...", f"a question of at most {MAX_QUESTION} characters"
            )
        parsed = parse(text)
        if parsed is None:
            return _not_understood(text, "I did not understand.")
        try:
            with _queries(self.store) as ran:
                reply = self._answers[parsed.form](parsed)
        except _NotUnderstood as error:
            return _not_understood(text, str(error))
        return Answer(
            question=text,
            understood=True,
            words=reply.words,
            form=parsed.form,
            slots=parsed.slots,
            answer=reply.answer,
            explanations=tuple(reply.explanations),
            sparql=tuple(ran),
        )

    def ask_audio(self, wav: bytes, recogniser: Any) -> tuple[Any, Answer]:
        """Hear the question in ``wav`` with ``recogniser`` (an :class:`api.ask.speech.Recogniser`)
        and answer it; returns (what was heard, the answer)."""
        heard = recogniser.hear(wav, self.names.get())
        if heard.text is None or parse(heard.text) is None:
            return heard, _not_understood(
                heard.text or "", "I did not hear a question I understand."
            )
        return heard, self.ask(heard.text)

    # Episodes ----------------------------------------------------------------------------------

    def _cue(self, parsed: Parsed) -> tuple[Cue, str, str]:
        agent_text = parsed.slots["agent"]
        activity_text = parsed.slots["activity"]
        if activity_text.lower().startswith("the "):
            activity_text = activity_text[4:]
        agent = self.names.find(agent_text, "participant") or agent_text
        activity = self.names.find(activity_text, "activity") or activity_text
        return Cue(activity, agent=agent), agent, activity

    def _episode_when(self, parsed: Parsed) -> _Reply:
        cue, agent, activity = self._cue(parsed)
        which = parsed.slots["which"]
        try:
            found = self.episodes.recall(cue, which=which)  # type: ignore[arg-type]
        except NotFoundError:
            return _Reply(f"I do not remember {agent} doing {activity}.", {"found": False})
        return _Reply(
            f"The {which} time {agent} did {activity} was {found.when}.",
            {"found": True, "episode": to_jsonable(found.episode), "when": found.when},
        )

    def _episode_count(self, parsed: Parsed) -> _Reply:
        cue, agent, activity = self._cue(parsed)
        n = self.episodes.count(cue)
        if n == 0:
            return _Reply(f"{agent} never did {activity}.", {"count": 0})
        times = {1: "once", 2: "twice"}.get(n, f"{n} times")
        return _Reply(f"{agent} did {activity} {times}.", {"count": n})

    def _episode_between(self, parsed: Parsed) -> _Reply:
        phrase = parsed.slots["time"]
        now = self.episodes.clock()
        start, end = time_window(phrase, now)
        found = self.episodes.between(start, end, now=now)
        data = {
            "from": start.isoformat(),
            "to": end.isoformat(),
            "episodes": [to_jsonable(r.episode) for r in found],
        }
        if not found:
            return _Reply(f"Nothing that I remember happened {phrase}.", data)
        parts = []
        for r in found:
            who = ", ".join(r.episode.participants)
            parts.append(f"{r.episode.activity}{f' with {who}' if who else ''} ({r.when})")
        return _Reply(f"{phrase.capitalize()}: " + "; ".join(parts) + ".", data)

    def _episode_who(self, parsed: Parsed) -> _Reply:
        cue, agent, activity = self._cue(parsed)
        which = parsed.slots.get("which", "last")
        try:
            found = self.episodes.recall(cue, which=which)  # type: ignore[arg-type]
        except NotFoundError:
            return _Reply(f"I do not remember {agent} doing {activity}.", {"found": False})
        others = [p for p in found.episode.participants if p.lower() != agent.lower()]
        data = {"found": True, "episode": to_jsonable(found.episode), "others": others}
        if not others:
            return _Reply(f"Only {agent} was there, {found.when}.", data)
        return _Reply(
            f"{_join(others)} {'was' if len(others) == 1 else 'were'} there when {agent} "
            f"did {activity}, {found.when}.",
            data,
        )

    # The scene memory --------------------------------------------------------------------------

    def _thing(self, parsed: Parsed) -> list[tuple[str, str, str]]:
        triples = parse_thing(parsed.slots["thing"])
        if triples is None:
            raise _NotUnderstood(
                f"I did not understand {parsed.slots['thing']!r}: I understand objects and "
                "relations such as 'a ball on a table' (objects: ball, sphere, cone, cup, "
                "cylinder, table, plane, ...; relations: on, under, behind, in front of, left "
                "of, right of, parallel to, perpendicular to)."
            )
        return triples

    def _class_words(self, cls: NamedNode) -> str:
        scores = self.scenes.reads.item_scores(cls)
        seen = self.scenes.reads.seen(cls)
        last = seen[-1][1] if seen else None
        how = f"seen {_times(scores.store_count)}"
        if last is not None:
            how += f", last {say_when(last, self.scenes.reads.now())}"
        return f"{local(cls)} ({how}; level {scores.level})"

    def _recall(self, parsed: Parsed) -> tuple[Any, str]:
        triples = self._thing(parsed)
        result = self.scenes.retrieve(triples)
        return result, parsed.slots["thing"]

    def _retrieval_json(self, result: Any) -> dict[str, Any]:
        return {
            "recalled": result.recalled.value if result.recalled else None,
            "exact": result.exact.value if result.exact else None,
            "generalisations": [[r.cls.value, r.confidence] for r in result.generalisations],
            "specialisations": [[m.cls.value, m.similarity] for m in result.specialisations],
            "similar": [[m.cls.value, m.similarity] for m in result.similar],
        }

    def _scene_know(self, parsed: Parsed) -> _Reply:
        result, thing = self._recall(parsed)
        data = self._retrieval_json(result)
        if result.recalled is None:
            return _Reply(f"I know nothing about {thing}.", data)
        containing = ([result.exact] if result.exact else []) + [
            m.cls for m in result.specialisations
        ]
        recalled = result.recalled
        definition = self._definition(recalled)
        words = f"I recall {self._class_words(recalled)}: {definition}."
        if len(containing) > 1:
            words += f" {_count(len(containing), 'kind')} of scene I know have {thing}."
        elif not containing:
            words += f" It is the closest I know; I have never seen {thing} as such."
        return _Reply(words, data, [explain_level(self.scenes, recalled)])

    def _definition(self, cls: NamedNode) -> str:
        """What the class asks for, in words (its own restrictions, as met by itself)."""
        return _describe(explain_subsumption(self.scenes, cls, cls).parents[0].restrictions)

    def _scene_seen(self, parsed: Parsed) -> _Reply:
        result, thing = self._recall(parsed)
        data = self._retrieval_json(result)
        containing = ([result.exact] if result.exact else []) + [
            m.cls for m in result.specialisations
        ]
        data["seen"] = bool(containing)
        if not containing:
            words = f"No, I have not seen {thing}."
            if result.similar:
                words += f" The closest I have seen is {local(result.similar[0].cls)}."
            return _Reply(words, data)
        listed = ", ".join(self._class_words(c) for c in containing[:3])
        if len(containing) == 1:
            return _Reply(f"Yes, I have seen {thing}: in {listed}.", data)
        return _Reply(
            f"Yes, I have seen {thing} in {_count(len(containing), 'kind')} of scene; the "
            f"closest: {listed}.",
            data,
        )

    def _scene_best(self, parsed: Parsed) -> _Reply:
        counts = self.scenes.reads.maxima()
        classes, items, best = counts["classes"], counts["items"], self.scenes.reads.best(3)
        if not best:
            return _Reply("I remember nothing yet.", {"best": []})
        top = best[0][1] or 1.0
        parts = [
            f"{local(cls)}, {self._definition(cls)} (score {zeta / top:.2f})" for cls, zeta in best
        ]
        return _Reply(
            f"Of {_count(classes, 'kind')} of scene, I remember best "
            + "; then ".join(parts)
            + ".",
            {"best": [[c.value, z / top] for c, z in best], "classes": classes, "scenes": items},
            [explain_level(self.scenes, best[0][0])],
        )

    def _scene_forgot(self, parsed: Parsed) -> _Reply:
        phrase = parsed.slots.get("time")
        bound: dict[str, NamedNode | Literal] = {"g": TRASH}
        data: dict[str, Any] = {}
        if phrase is not None:
            start, end = time_window(phrase, self.scenes.reads.now())
            bound["from"] = to_literal(start)
            bound["to"] = to_literal(end)
            data |= {"from": start.isoformat(), "to": end.isoformat()}
        rows = self.store.select("ask_forgotten", **bound)
        classes = [r["subject"] for r in rows if r["kind"].value == "class"]
        scenes = [r["subject"] for r in rows if r["kind"].value == "scene"]
        data |= {"classes": [c.value for c in classes], "scenes": [s.value for s in scenes]}
        when = phrase or "so far"
        if not rows:
            return _Reply(f"I forgot nothing {when}.", data)
        parts = [local(c) for c in classes]  # type: ignore[arg-type]
        if scenes:
            parts.append(_count(len(scenes), "experienced scene"))
        explanations: list[Explanation] = [
            explain_forgetting(self.scenes, c)  # type: ignore[arg-type]
            for c in classes[:3]
            if self.scenes.reads.trashed(c) is not None  # type: ignore[arg-type]
        ]
        return _Reply(f"{when.capitalize()} I forgot {_join(parts)}.", data, explanations)

    # Explanations ------------------------------------------------------------------------------

    def _explain_forget(self, parsed: Parsed) -> _Reply:
        name = parsed.slots["name"]
        iri = _iri(name)
        if self.scenes.reads.trashed(iri) is not None:
            forgetting = explain_forgetting(self.scenes, iri)
            return _Reply(forgetting.words, {"forgotten": True}, [forgetting])
        try:
            level = explain_level(self.scenes, iri)
        except MemoryReasonerError:
            return _Reply(f"I never knew {name}.", {"forgotten": False, "known": False})
        return _Reply(
            f"I have not forgotten {name}. {level.words}",
            {"forgotten": False, "known": True},
            [level],
        )

    def _explain_kind(self, parsed: Parsed) -> _Reply:
        name, other = parsed.slots["name"], parsed.slots["other"]
        for each in (name, other):
            if self.scenes.reads.trashed(_iri(each)) is not None:
                return _Reply(f"I forgot {each}; restore it to compare.", {"kind_of": None})
        try:
            placement = explain_subsumption(self.scenes, _iri(name), _iri(other))
        except MemoryReasonerError:
            unknown = name if self.scenes.reads.trashed(_iri(name)) is None else other
            return _Reply(f"I do not know {unknown}.", {"kind_of": None})
        words = ("Yes. " if placement.is_kind else "No. ") + placement.words
        return _Reply(words, {"kind_of": placement.is_kind}, [placement])

    def _explain_learn(self, parsed: Parsed) -> _Reply:
        name = parsed.slots["name"]
        try:
            learning = explain_learning(self.scenes, _iri(name))
        except MemoryReasonerError:
            return _Reply(f"{name} is not a class I know now.", {"known": False})
        return _Reply(learning.words, {"known": True}, [learning])

    def _explain_level(self, parsed: Parsed) -> _Reply:
        name = parsed.slots["name"]
        try:
            level = explain_level(self.scenes, _iri(name))
        except MemoryReasonerError:
            return _Reply(f"{name} is not something I remember now.", {"known": False})
        return _Reply(level.words, {"known": True, "level": level.level}, [level])

    def _explain_any(self, parsed: Parsed) -> _Reply:
        name = parsed.slots["name"]
        try:
            explanations = explain(self.scenes, _iri(name))
        except MemoryReasonerError:
            return _Reply(f"I never knew {name}.", {"known": False})
        words: list[str] = []
        for explanation in explanations:  # a forgetting explanation says the restore's words
            if not any(explanation.words in said for said in words):
                words.append(explanation.words)
        return _Reply(" ".join(words), {"known": True}, explanations)

    def _explain_last_scene(self, parsed: Parsed) -> _Reply:
        items = self.scenes.reads.items()
        if not items:
            return _Reply("I have not seen any scene yet.", {"scene": None})
        last = items[-1]
        why = explain_scene(self.scenes, last)
        data = {"scene": last.value, "recognised": not isinstance(why, LearningExplanation)}
        if isinstance(why, LearningExplanation):
            prefix = "I did not recognise it. " if parsed.slots.get("negated") else ""
            return _Reply(prefix + why.words, data, [why])
        prefix = "But I did recognise it. " if parsed.slots.get("negated") else ""
        return _Reply(prefix + why.words, data, [why])

    # History -----------------------------------------------------------------------------------

    def _history_score(self, parsed: Parsed) -> _Reply:
        name = parsed.slots["name"]
        events = history.events(self.store, _iri(name))
        data: dict[str, Any] = {"class": _iri(name).value, "events": [e.to_json() for e in events]}
        if not events:
            return _Reply(f"I have no history of {name}.", data)
        first, last = events[0], events[-1]
        when = self.scenes.reads.now()
        parts = [f"I {_past(first.kind)} {name} {say_when(_parse(first.time), when)}"]
        counts = {k: sum(1 for e in events if e.kind == k) for k in ("reinforced", "retrieved")}
        if counts["reinforced"]:
            parts.append(f"saw it again {_times(counts['reinforced'])}")
        if counts["retrieved"]:
            parts.append(f"recalled it {_times(counts['retrieved'])}")
        levels = [e.level for e in events if e.kind == "level" and e.level]
        words = _join(parts) + "."
        if levels:
            words += f" Its level went {' then '.join(levels)}."
        scores = [e.score for e in events if e.score is not None]
        if scores:
            words += f" Its score went from {scores[0]:.2f} to {scores[-1]:.2f}."
        if last.kind == "forgotten":
            words += f" I forgot it {say_when(_parse(last.time), when)}."
        return _Reply(words, data)

    def _history_as_of(self, parsed: Parsed) -> _Reply:
        phrase = parsed.slots["time"]
        end = time_window(phrase, self.scenes.reads.now())[1]
        states = history.as_of(self.store, end)
        data: dict[str, Any] = {
            "time": end.isoformat(),
            "classes": [s.to_json() for s in states],
        }
        if not states:
            return _Reply(f"I knew no kind of scene {phrase}.", data)
        best = sorted(states, key=lambda s: (-(s.score or 0.0), s.cls.value))[:3]
        listed = _join([f"{local(s.cls)}{f' ({s.level})' if s.level else ''}" for s in best])
        return _Reply(
            f"{phrase.capitalize()} I knew {_count(len(states), 'kind')} of scene; best {listed}.",
            data,
        )


class _NotUnderstood(Exception):
    """A question fits a form, but a part of it does not (its words say which)."""


def _not_understood(text: str, words: str) -> Answer:
    suggestions = tuple(closest(text)) if text else tuple(f.example for f in FORMS[:3])
    return Answer(
        question=text,
        understood=False,
        words=f"{words} I understand questions like: "
        + "; ".join(f'"{s}?"' for s in suggestions)
        + ".",
        suggestions=suggestions,
    )


def _parse(text: str) -> dt.datetime:
    return dt.datetime.fromisoformat(text)


def _past(kind: str) -> str:
    return {"learned": "learned", "restored": "restored"}.get(kind, f"first {kind}")


def _times(n: int) -> str:
    return {1: "once", 2: "twice"}.get(n, f"{n} times")


def _count(n: int, noun: str) -> str:
    return f"{n} {noun}{'' if n == 1 else 's'}"


def _join(parts: list[str]) -> str:
    if len(parts) <= 1:
        return "".join(parts)
    return ", ".join(parts[:-1]) + " and " + parts[-1]
