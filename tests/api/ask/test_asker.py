"""Each question form answered from the lived week (tests/api/ask/conftest.py)."""

import json

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from api.ask import Asker
from kg.errors import InvalidInputError
from ontologies.vocab import engram
from tests.api.ask.conftest import TWO_BALLS


def ask(asker: Asker, text: str) -> dict[str, object]:
    answer = asker.ask(text)
    assert answer.understood, answer.words
    body = answer.to_json()
    json.dumps(body)  # all of it is JSON
    return body


def test_when_did_someone_last_and_first_do_something(asker: Asker) -> None:
    last = ask(asker, "When did Anna last show you motor babbling?")
    assert last["words"] == "The last time Anna did motor babbling was yesterday at 14:00."
    first = ask(asker, "when did anna first do motor babbling")  # names in any case
    assert first["words"] == (
        "The first time Anna did motor babbling was two days ago, on March 2nd."
    )
    assert first["answer"]["episode"]["begin"] == "2026-03-02T09:00:00+00:00"  # type: ignore[index]
    [query] = [q for q in last["sparql"] if "ORDER BY DESC(?begin)" in q]  # type: ignore[attr-defined]
    assert "VALUES" in query and '"motor babbling"' in query and "participant/Anna" in query


def test_when_for_something_that_never_happened(asker: Asker) -> None:
    body = ask(asker, "when did HyungJin last do waving")
    assert body["words"] == "I do not remember HyungJin doing waving."
    assert body["answer"] == {"found": False}


def test_how_many_times(asker: Asker) -> None:
    assert ask(asker, "How many times did Anna do motor babbling?")["words"] == (
        "Anna did motor babbling twice."
    )
    never = ask(asker, "how many times did HyungJin do waving")
    assert never["words"] == "HyungJin never did waving." and never["answer"] == {"count": 0}


def test_what_happened_yesterday_afternoon(asker: Asker) -> None:
    body = ask(asker, "What happened yesterday afternoon?")
    assert body["words"] == (
        "Yesterday afternoon: motor babbling with Anna, HyungJin, Peter (yesterday at 14:00); "
        "pointing with HyungJin (yesterday at 15:30)."
    )
    assert body["answer"]["from"] == "2026-03-03T12:00:00+00:00"  # type: ignore[index]
    assert ask(asker, "what happened last night")["words"] == (
        "Nothing that I remember happened last night."
    )


def test_who_was_there(asker: Asker) -> None:
    body = ask(asker, "Who was there when Anna last did motor babbling?")
    assert body["words"] == (
        "HyungJin and Peter were there when Anna did motor babbling, yesterday at 14:00."
    )
    first = ask(asker, "who was there the first time Anna did motor babbling")
    assert first["answer"]["others"] == ["Peter"]  # type: ignore[index]
    alone = ask(asker, "who was there when HyungJin did pointing")
    assert alone["words"].startswith("Only HyungJin was there")  # type: ignore[union-attr]


def test_what_do_you_know_about_a_ball_on_a_table(asker: Asker) -> None:
    before = asker.scenes.reads.item_scores(engram("Scene-3")).retrieve_count
    body = ask(asker, "What do you know about a ball on a table?")
    assert body["answer"]["recalled"] == engram("Scene-3").value  # type: ignore[index]
    assert str(body["words"]).startswith("I recall Scene-3 (seen once")
    assert "2 kinds of scene I know have a ball on a table" in str(body["words"])
    # recalling strengthens what was recalled, as any retrieval does
    assert asker.scenes.reads.item_scores(engram("Scene-3")).retrieve_count == before + 1
    assert [e["kind"] for e in body["explanations"]] == ["level"]  # type: ignore[union-attr]


def test_have_you_seen(asker: Asker) -> None:
    seen = ask(asker, "Have you seen a cone behind a sphere?")
    assert seen["answer"]["seen"] is True  # type: ignore[index]
    assert str(seen["words"]).startswith("Yes, I have seen a cone behind a sphere: in Scene-4 (")
    on_table = ask(asker, "have you seen a ball on a table")
    assert str(on_table["words"]).startswith(
        "Yes, I have seen a ball on a table in 2 kinds of scene; the closest: Scene-3 (seen once"
    )
    not_seen = ask(asker, "have you seen a cup on a table")
    assert not_seen["answer"]["seen"] is False  # type: ignore[index]
    assert str(not_seen["words"]).startswith("No, I have not seen a cup on a table.")


def test_a_thing_the_grammar_cannot_read_is_not_understood(asker: Asker) -> None:
    answer = asker.ask("have you seen a dragon on a table")
    assert not answer.understood
    assert "I did not understand 'a dragon on a table'" in answer.words
    assert answer.suggestions


def test_what_do_you_remember_best(asker: Asker) -> None:
    body = ask(asker, "What do you remember best?")
    best = body["answer"]["best"]  # type: ignore[index]
    assert best[0] == [engram("Scene-1").value, 1.0]
    assert str(body["words"]).startswith("Of 3 kinds of scene, I remember best Scene-1")


def test_what_did_you_forget(asker: Asker) -> None:
    body = ask(asker, "What did you forget this week?")
    assert body["words"] == "This week I forgot Scene-2 and 1 experienced scene."
    assert body["answer"]["classes"] == [engram("Scene-2").value]  # type: ignore[index]
    assert [e["kind"] for e in body["explanations"]] == ["forgetting"]  # type: ignore[union-attr]
    query = body["sparql"][0]  # type: ignore[index]
    assert "forgottenAt" in query and "2026-03-02T00:00:00+00:00" in query
    assert any("isLiteral(?o)" in q for q in body["sparql"])  # type: ignore[attr-defined]
    assert ask(asker, "what did you forget today")["words"] == "I forgot nothing today."


def test_why_did_you_forget(asker: Asker) -> None:
    body = ask(asker, "Why did you forget Scene-2?")
    assert str(body["words"]).startswith(
        "I forgot Scene-2 at 2026-03-03T08:00:00+00:00 because its level was WEAK at 3 "
        "consecutive sleep passes (I forget after 3), it was 24.0 h old"
    )
    assert "I can restore Scene-2 with experience-31" in str(body["words"])
    assert any("isLiteral(?o)" in q and "Scene-2" in q for q in body["sparql"])  # type: ignore[attr-defined]
    live = ask(asker, "why did you forget scene one")
    assert str(live["words"]).startswith("I have not forgotten Scene-1.")
    assert ask(asker, "why did you forget scene 99")["words"] == "I never knew Scene-99."


def test_why_is_one_a_kind_of_another(asker: Asker) -> None:
    yes = ask(asker, "Why is Scene-1 a kind of Scene-3?")
    assert yes["answer"] == {"kind_of": True}
    assert str(yes["words"]).startswith("Yes. Scene-1 is a kind of Scene-3 because it meets")
    no = ask(asker, "why is scene three a kind of scene one")
    assert no["answer"] == {"kind_of": False}
    assert str(no["words"]).startswith("No. Scene-3 is not a kind of Scene-1: Scene-1 asks for")
    gone = ask(asker, "why is scene two a kind of scene one")
    assert gone["words"] == "I forgot Scene-2; restore it to compare."


def test_why_did_you_not_recognise_the_last_scene(asker: Asker) -> None:
    body = ask(asker, "Why didn't you recognise the last scene?")
    assert body["answer"] == {"scene": engram("experience-33").value, "recognised": False}
    assert str(body["words"]).startswith("I did not recognise it. I learned Scene-4 because")


def test_the_last_scene_recognised_says_so(asker: Asker) -> None:
    asker.scenes.store_scene(TWO_BALLS)
    body = ask(asker, "why did you not recognise the last scene")
    assert body["answer"]["recognised"] is True  # type: ignore[index]
    assert str(body["words"]).startswith(
        "But I did recognise it. I recognised experience-34 as Scene-1"
    )


def test_why_did_you_learn_and_how_well_do_you_remember(asker: Asker) -> None:
    learn = ask(asker, "why did you learn Scene-1")
    assert learn["words"] == (
        "I learned Scene-1 because no class I knew before it fitted its scene: I knew none."
    )
    level = ask(asker, "how well do you remember scene four")
    assert level["answer"]["known"] is True and level["explanations"][0]["kind"] == "level"  # type: ignore[index]


def test_explain_anything(asker: Asker) -> None:
    body = ask(asker, "explain experience 31")
    assert [e["kind"] for e in body["explanations"]] == ["forgetting", "restore"]  # type: ignore[union-attr]
    assert str(body["words"]).count("I cannot restore experience-31") == 1
    assert "restore the class first" in str(body["words"])


def test_how_did_the_score_change(asker: Asker) -> None:
    body = ask(asker, "How did the score of scene two change?")
    answer = body["answer"]
    kinds = [e["kind"] for e in answer["events"]]  # type: ignore[index]
    assert kinds[0] == "learned" and kinds[-1] == "forgotten" and "level" in kinds
    words = str(body["words"])
    assert words.startswith("I learned Scene-2 two days ago") and "WEAK" in words
    assert words.endswith("I forgot it yesterday at 08:00.")
    assert any("eventClass" in q for q in body["sparql"])  # type: ignore[attr-defined]
    assert ask(asker, "what happened to Scene-99")["words"] == "I have no history of Scene-99."


def test_what_did_you_know_then(asker: Asker) -> None:
    before = ask(asker, "what did you know last week")  # the week before the memory began
    assert before["words"] == "I knew no kind of scene last week."
    yesterday = ask(asker, "what did you know yesterday")
    classes = yesterday["answer"]["classes"]  # type: ignore[index]
    assert {c["class"].rsplit("#")[-1] for c in classes} == {"Scene-1", "Scene-3"}
    assert str(yesterday["words"]).startswith("Yesterday I knew 2 kinds of scene; best Scene-1")


def test_a_question_outside_the_grammar_gets_the_closest_forms(asker: Asker) -> None:
    answer = asker.ask("why did you forgot scene 4")
    assert not answer.understood and answer.form is None and answer.sparql == ()
    assert answer.words.startswith("I did not understand. I understand questions like:")
    assert answer.suggestions[0] == "why did you forget Scene-4"


@pytest.mark.parametrize(
    ("text", "fragment"),
    [("", "expected a question in words"), ("   ", "a question in words"), ("x" * 501, "500")],
)
def test_bad_text_is_refused(asker: Asker, text: str, fragment: str) -> None:
    with pytest.raises(InvalidInputError, match=fragment):
        asker.ask(text)


def test_a_name_added_after_the_names_were_read_is_found(asker: Asker) -> None:
    from episodes import ArgumentSpec

    assert ask(asker, "how many times did anna do motor babbling")["answer"] == {"count": 2}
    asker.names.retry_s = 0.0  # the cache reads the names again on a miss at once
    episode = asker.episodes.begin("juggling", arguments=[ArgumentSpec("agent", "Zoe")])
    asker.episodes.end(episode.id)
    assert ask(asker, "how many times did zoe do Juggling")["words"] == "Zoe did juggling once."


FRAGMENTS = [
    "when did",
    "last",
    "first",
    "how many times did",
    "do",
    "what happened",
    "who was there when",
    "have you seen",
    "a ball on a table",
    "why is",
    "a kind of",
    "scene 4",
    "experience 31",
    "scene ninety nine",
    "why did you forget",
    "explain",
    "Anna",
    "motor babbling",
    "ünïcode ✓",
    "?",
    "x" * 60,
]


@settings(
    max_examples=60, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture]
)
@given(st.lists(st.sampled_from(FRAGMENTS), min_size=1, max_size=6))
def test_any_question_is_answered_or_refused_never_crashes(asker: Asker, words: list[str]) -> None:
    text = " ".join(words)
    try:
        answer = asker.ask(text)
    except InvalidInputError as error:
        assert error.field in ("text", "activity", "agent")
        return
    assert answer.words and json.dumps(answer.to_json())
