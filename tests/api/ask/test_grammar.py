"""The question grammar: each form parses with its slots, the rest gets the closest forms."""

import datetime as dt

import pytest

from api.ask.grammar import FORMS, closest, jsgf, normalise, parse, parse_thing
from api.ask.vocabulary import Names, number_from_words, say_number, time_window

CASES = [
    (
        "When did HyungJin last show you motor babbling?",
        "episode_when",
        {"agent": "HyungJin", "which": "last", "activity": "motor babbling"},
    ),
    (
        "when did anna first do pointing",
        "episode_when",
        {"agent": "anna", "which": "first", "activity": "pointing"},
    ),
    (
        "When was the last time Anna did waving?",
        "episode_when",
        {"which": "last", "agent": "Anna", "activity": "waving"},
    ),
    (
        "How many times did Peter do waving?",
        "episode_count",
        {"agent": "Peter", "activity": "waving"},
    ),
    ("how often did Anna show you motor babbling", "episode_count", None),
    ("What happened yesterday afternoon?", "episode_between", {"time": "yesterday afternoon"}),
    ("what happened this week", "episode_between", {"time": "this week"}),
    (
        "Who was there when Anna last did motor babbling?",
        "episode_who",
        {"agent": "Anna", "which": "last", "activity": "motor babbling"},
    ),
    (
        "who was there the first time HyungJin did pointing",
        "episode_who",
        {"which": "first", "agent": "HyungJin", "activity": "pointing"},
    ),
    (
        "What do you know about a ball on a table?",
        "scene_know",
        {"thing": "a ball on a table"},
    ),
    ("Have you seen a cone behind a sphere?", "scene_seen", {"thing": "a cone behind a sphere"}),
    ("have you ever seen a cup left of a ball", "scene_seen", None),
    ("What do you remember best?", "scene_best", {}),
    ("What did you forget this week?", "scene_forgot", {"time": "this week"}),
    ("what did you forget", "scene_forgot", {}),
    ("Why did you forget Scene-4?", "explain_forget", {"name": "Scene-4"}),
    ("why did you forget scene four", "explain_forget", {"name": "Scene-4"}),
    (
        "Why is Scene-2 a kind of Scene-1?",
        "explain_kind",
        {"name": "Scene-2", "other": "Scene-1"},
    ),
    ("why is scene twenty one a kind of scene 3", "explain_kind", None),
    (
        "Why didn't you recognize the last scene?",
        "explain_last_scene",
        {"negated": "true"},
    ),
    ("why did you recognise the last scene", "explain_last_scene", {}),
    ("Why did you learn Scene-3?", "explain_learn", {"name": "Scene-3"}),
    ("How well do you remember scene one?", "explain_level", {"name": "Scene-1"}),
    ("explain experience 31", "explain_any", {"name": "experience-31"}),
    ("How did the score of scene two change?", "history_score", {"name": "Scene-2"}),
    ("what happened to Scene-4", "history_score", {"name": "Scene-4"}),
    ("What did you know yesterday?", "history_as_of", {"time": "yesterday"}),
]


@pytest.mark.parametrize(("text", "form", "slots"), CASES)
def test_each_form_parses_with_its_slots(
    text: str, form: str, slots: dict[str, str] | None
) -> None:
    parsed = parse(text)
    assert parsed is not None and parsed.form == form
    if slots is not None:
        assert parsed.slots == slots


def test_every_form_is_covered_by_the_table() -> None:
    assert {form for _, form, _ in CASES} == {f.name for f in FORMS}


@pytest.mark.parametrize("form", FORMS, ids=lambda f: f.name)
def test_every_example_parses_as_its_own_form(form: object) -> None:
    parsed = parse(form.example)  # type: ignore[attr-defined]
    assert parsed is not None and parsed.form == form.name  # type: ignore[attr-defined]


@pytest.mark.parametrize(
    "text", ["make me a sandwich", "when did", "why is Scene-2", "what happened on Mars", ""]
)
def test_questions_outside_the_grammar_do_not_parse(text: str) -> None:
    assert parse(text) is None


def test_the_closest_forms_share_the_most_wording() -> None:
    assert closest("why did you forgot scene 4", 1) == ["why did you forget Scene-4"]
    assert closest("how many time did Anna waving", 1) == ["how many times did Anna do waving"]
    assert len(closest("anything at all")) == 3


def test_normalise_keeps_the_case_of_names_and_evens_spelling() -> None:
    assert normalise("Why didn't you recognize it, HyungJin?") == (
        "Why did you not recognise it HyungJin"
    )


@pytest.mark.parametrize(
    ("thing", "triples"),
    [
        ("a ball on a table", [("Sphere", "isAboveOf", "Plane")]),
        ("the cone behind a sphere", [("Cone", "isBehindOf", "Sphere")]),
        (
            "a cup to the left of a ball and a ball on the table",
            [("Cylinder", "isLeftOf", "Sphere"), ("Sphere", "isAboveOf", "Plane")],
        ),
        ("a ball near a table", None),
        ("a dragon on a table", None),
    ],
)
def test_things_become_relation_triples(
    thing: str, triples: list[tuple[str, str, str]] | None
) -> None:
    assert parse_thing(thing) == triples


def test_numbers_in_words_and_digits() -> None:
    assert [number_from_words(w) for w in ("one", "twelve", "forty two", "90", "ninety")] == [
        1,
        12,
        42,
        90,
        90,
    ]
    assert number_from_words("forty eleven") is None and number_from_words("lots") is None
    assert all(number_from_words(say_number(n)) == n for n in range(1, 100))


WEDNESDAY = dt.datetime(2026, 3, 4, 10, 0, tzinfo=dt.UTC)


@pytest.mark.parametrize(
    ("phrase", "start", "end"),
    [
        ("yesterday afternoon", "2026-03-03T12:00:00", "2026-03-03T18:00:00"),
        ("this morning", "2026-03-04T06:00:00", "2026-03-04T10:00:00"),
        ("today", "2026-03-04T00:00:00", "2026-03-04T10:00:00"),
        ("this week", "2026-03-02T00:00:00", "2026-03-04T10:00:00"),
        ("last week", "2026-02-23T00:00:00", "2026-03-02T00:00:00"),
        ("last night", "2026-03-03T18:00:00", "2026-03-04T06:00:00"),
    ],
)
def test_time_phrases_name_windows_of_the_local_calendar(phrase: str, start: str, end: str) -> None:
    window = time_window(phrase, WEDNESDAY)
    assert [t.isoformat() for t in window] == [start + "+00:00", end + "+00:00"]


def test_the_jsgf_grammar_holds_every_form_and_only_sayable_names() -> None:
    names = Names(activities=("motor babbling", "x_42"), participants=("HyungJin", "Anna"))
    text = jsgf(names, known={"anna", "motor", "babbling"})
    assert text.startswith("#JSGF V1.0;")
    assert "<agent> = (anna);" in text and "<activity> = (motor babbling);" in text
    assert text.count("public <question>") == 1
    assert all(f"({form.jsgf})" in text for form in FORMS)
