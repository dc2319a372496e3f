"""The question grammar: every form a question may take, as patterns over words (no language
model), the same forms as a JSGF grammar for the speech recogniser, and the closest forms to a
question that fits none.

A form's slots are filled from the question's own words: ``agent`` and ``activity`` (episodes),
``thing`` (objects and relations: "a ball on a table and a cup left of the ball"), ``time``
(:data:`api.ask.vocabulary.TIMES`), ``name`` and ``other`` (a class "Scene-4", "scene four",
or an experienced scene "experience 3").

>>> parse("When did Anna last show you motor babbling?").slots
{'agent': 'Anna', 'which': 'last', 'activity': 'motor babbling'}
>>> parse("have you seen a cone behind a sphere").form
'scene_seen'
>>> parse("Why is scene two a kind of Scene-1?").slots
{'name': 'Scene-2', 'other': 'Scene-1'}
>>> parse("make me a sandwich") is None
True
"""

import difflib
import re
from dataclasses import dataclass

from api.ask.vocabulary import (
    NUMBER_WORDS,
    OBJECTS,
    RELATIONS,
    TIMES,
    Names,
    number_from_words,
    say_number,
)

__all__ = ["FORMS", "Form", "Parsed", "closest", "jsgf", "normalise", "parse", "parse_thing"]

_DO = r"(?:(?:show you|show me|do the|do|perform|practise|practice|play|have) )?"
_DID = r"(?:(?:showed you|showed me|did the|did|performed|practised|practiced|played|had) )?"
_NUMBER = r"(?:\d+|(?:" + "|".join(NUMBER_WORDS) + r")(?: (?:" + "|".join(NUMBER_WORDS[:9]) + "))?)"
_NAME = rf"(?:scene|experience) ?-? ?{_NUMBER}"
_TIME = "|".join(sorted(TIMES, key=len, reverse=True))


@dataclass(frozen=True)
class Form:
    """One form of question: its name, what it asks, patterns, and examples to suggest."""

    name: str
    patterns: tuple[str, ...]
    example: str
    jsgf: str
    """The form as a JSGF rule body over the rules ``<agent>``, ``<activity>``, ``<thing>``,
    ``<time>`` and ``<name>``."""


FORMS: tuple[Form, ...] = (
    Form(
        "episode_when",
        (
            rf"when did (?P<agent>.+?) (?P<which>last|first) {_DO}(?P<activity>.+)",
            rf"when was the (?P<which>last|first) time (?P<agent>.+?) {_DID}(?P<activity>.+)",
        ),
        "when did Anna last show you motor babbling",
        "(when did <agent> (last | first) [show you | do] <activity>)"
        " | (when was the (last | first) time <agent> did <activity>)",
    ),
    Form(
        "episode_count",
        (rf"how (?:many times|often) did (?P<agent>.+?) {_DO}(?P<activity>.+)",),
        "how many times did Anna do waving",
        "how (many times | often) did <agent> [show you | do] <activity>",
    ),
    Form(
        "episode_between",
        (rf"what happened (?P<time>{_TIME})", rf"what did you do (?P<time>{_TIME})"),
        "what happened yesterday afternoon",
        "(what happened | what did you do) <time>",
    ),
    Form(
        "episode_who",
        (
            rf"who was (?:there|with (?:them|him|her)) when (?P<agent>.+?) "
            rf"(?:(?P<which>last|first) )?{_DID}{_DO}(?P<activity>.+)",
            rf"who was (?:there|with (?:them|him|her)) the (?P<which>last|first) time "
            rf"(?P<agent>.+?) {_DID}(?P<activity>.+)",
        ),
        "who was there when Anna last did motor babbling",
        "who was there ((when <agent> [last | first] [did | showed you] <activity>)"
        " | (the (last | first) time <agent> did <activity>))",
    ),
    Form(
        "scene_know",
        (r"what do you (?:know|remember) about (?P<thing>.+)",),
        "what do you know about a ball on a table",
        "what do you know about <thing>",
    ),
    Form(
        "scene_seen",
        (r"(?:have|did) you (?:ever )?(?:seen|see) (?P<thing>.+)",),
        "have you seen a cone behind a sphere",
        "have you [ever] seen <thing>",
    ),
    Form(
        "scene_best",
        (r"what do you remember (?:best|most)", r"what do you know best"),
        "what do you remember best",
        "what do you remember (best | most)",
    ),
    Form(
        "scene_forgot",
        (rf"what did you forget(?: (?P<time>{_TIME}))?",),
        "what did you forget this week",
        "what did you forget [<time>]",
    ),
    Form(
        "explain_last_scene",
        (
            rf"why did you (?P<negated>not )?recognise the last scene(?: as (?P<name>{_NAME}))?",
            r"why was the last scene (?P<negated>not )?recognised",
        ),
        "why did you not recognise the last scene",
        "why did you [not] recognise the last scene",
    ),
    Form(
        "explain_forget",
        (rf"why did you forget (?P<name>{_NAME})",),
        "why did you forget Scene-4",
        "why did you forget <name>",
    ),
    Form(
        "explain_kind",
        (rf"why is (?P<name>{_NAME}) (?:a kind|a subclass|a sort|a type) of (?P<other>{_NAME})",),
        "why is Scene-2 a kind of Scene-1",
        "why is <name> a kind of <name>",
    ),
    Form(
        "explain_learn",
        (rf"why did you learn (?P<name>{_NAME})",),
        "why did you learn Scene-2",
        "why did you learn <name>",
    ),
    Form(
        "explain_level",
        (
            rf"how well do you remember (?P<name>{_NAME})",
            rf"why do you (?:still )?remember (?P<name>{_NAME})",
        ),
        "how well do you remember Scene-1",
        "(how well | why) do you remember <name>",
    ),
    Form(
        "history_score",
        (
            rf"how (?:did|has) the score of (?P<name>{_NAME}) (?:change|changed)",
            rf"how (?:did|has) (?P<name>{_NAME}) (?:change|changed)",
            rf"what happened to (?P<name>{_NAME})",
        ),
        "how did the score of Scene-1 change",
        "(how did the score of <name> change) | (what happened to <name>)",
    ),
    Form(
        "history_as_of",
        (rf"what did you know (?P<time>{_TIME})",),
        "what did you know yesterday",
        "what did you know <time>",
    ),
    Form(
        "explain_any",
        (rf"(?:explain|tell me about) (?P<name>{_NAME})",),
        "explain Scene-3",
        "(explain | tell me about) <name>",
    ),
)

_COMPILED = [
    (form, [re.compile(p + r"\Z", re.IGNORECASE) for p in form.patterns]) for form in FORMS
]


@dataclass(frozen=True)
class Parsed:
    """A question that fits a form, with its slots filled."""

    form: str
    slots: dict[str, str]


def normalise(text: str) -> str:
    """Spelling and punctuation evened out, the case of the words kept (names need it)."""
    text = text.replace("\u2019", "'")
    text = re.sub(r"\bdidn't\b", "did not", text, flags=re.IGNORECASE)
    text = re.sub(r"\bwasn't\b", "was not", text, flags=re.IGNORECASE)
    text = re.sub(r"\bdid not you\b", "did you not", text, flags=re.IGNORECASE)
    text = re.sub(r"recogniz", "recognis", text, flags=re.IGNORECASE)
    text = re.sub(r"[?!.,;:\"]", " ", text)
    text = re.sub(r"\b(?:please|robot|engram)\b", " ", text, flags=re.IGNORECASE)
    return " ".join(text.split())


def _name(text: str) -> str:
    """ "scene four", "scene-4", "Scene 4" -> "Scene-4"; "experience 3" -> "experience-3"."""
    words = text.lower().replace("-", " ").split()
    number = number_from_words(" ".join(words[1:]))
    prefix = "Scene" if words[0] == "scene" else "experience"
    return f"{prefix}-{number}"


def parse(text: str) -> Parsed | None:
    """The form ``text`` fits and its slots, or None."""
    question = normalise(text)
    for form, patterns in _COMPILED:
        for pattern in patterns:
            match = pattern.match(question)
            if match is None:
                continue
            slots = {k: v for k, v in match.groupdict().items() if v is not None}
            for key in ("name", "other"):
                if key in slots:
                    slots[key] = _name(slots[key])
            for key in ("which", "time"):
                if key in slots:
                    slots[key] = slots[key].lower()
            if "negated" in slots:
                slots["negated"] = "true"
            return Parsed(form.name, slots)
    return None


_ARTICLE = r"(?:(?:a|an|the|some|one) )?"
_OBJECT = "|".join(sorted(OBJECTS, key=len, reverse=True))
_RELATION = "|".join(sorted(RELATIONS, key=len, reverse=True))
_TRIPLE = re.compile(
    rf"{_ARTICLE}(?P<s>{_OBJECT})s? (?P<r>{_RELATION}) {_ARTICLE}(?P<o>{_OBJECT})s?\Z",
    re.IGNORECASE,
)


def parse_thing(text: str) -> list[tuple[str, str, str]] | None:
    """Relation triples between object kinds from "a ball on a table and a cup behind the
    ball", or None when a part is not "object relation object"."""
    triples = []
    for part in re.split(r" and |, ", text.strip(), flags=re.IGNORECASE):
        match = _TRIPLE.match(part.strip())
        if match is None:
            return None
        s, r, o = (match[k].lower() for k in ("s", "r", "o"))
        triples.append((OBJECTS[s], RELATIONS[r], OBJECTS[o]))
    return triples


def closest(text: str, count: int = 3) -> list[str]:
    """The examples of the ``count`` forms whose wording is nearest to ``text``."""
    question = normalise(text).lower()
    ranked = sorted(
        FORMS,
        key=lambda f: -difflib.SequenceMatcher(None, question, f.example.lower()).ratio(),
    )
    return [f.example for f in ranked[:count]]


SPOKEN_OBJECTS = ("ball", "sphere", "cone", "cylinder", "cup", "table", "plane")
"""The object words the recogniser listens for: fewer than the text grammar reads, each far
from the others in sound ("apple" was heard for "cone", "can" for "cone")."""
SPOKEN_RELATIONS = (
    "on",
    "above",
    "under",
    "below",
    "behind",
    "in front of",
    "to the left of",
    "to the right of",
    "parallel to",
    "perpendicular to",
)
"""The relation phrases the recogniser listens for."""


def _alternatives(words: list[str]) -> str:
    return "(" + " | ".join(words) + ")" if words else "<VOID>"


def jsgf(names: Names, *, scene_numbers: int = 30, known: set[str] | None = None) -> str:
    """The grammar as JSGF for a recogniser: every form, with the memory's names in the slots.

    Names with words the recogniser cannot say (not in ``known``, when given) are left out.
    """

    def sayable(name: str) -> str | None:
        words = re.sub(r"[^a-z' ]", " ", name.lower()).split()
        if not words or (known is not None and any(w not in known for w in words)):
            return None
        return " ".join(words)

    agents = sorted({s for n in names.participants if (s := sayable(n))})
    activities = sorted({s for n in names.activities if (s := sayable(n))})
    numbers = [say_number(n) for n in range(1, scene_numbers + 1)]
    objects, relations = list(SPOKEN_OBJECTS), list(SPOKEN_RELATIONS)
    rules = [
        "#JSGF V1.0;",
        "grammar ask;",
        "public <question> = " + " | ".join(f"({f.jsgf})" for f in FORMS) + ";",
        f"<agent> = {_alternatives(agents)};",
        f"<activity> = {_alternatives(activities)};",
        f"<time> = {_alternatives(list(TIMES))};",
        f"<name> = (scene | experience) {_alternatives(numbers)};",
        "<object> = (a | the) " + _alternatives(objects) + ";",
        "<relation> = " + _alternatives(relations) + ";",
        "<thing> = <object> <relation> <object>;",
    ]
    return "\n".join(rules) + "\n"
