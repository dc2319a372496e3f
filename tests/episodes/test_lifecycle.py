"""Episodes: begin and end, arguments, memory snapshots, annotations, scene links, deletion."""

import datetime as dt

import pytest
from pyoxigraph import Literal

from episodes import (
    ArgumentSpec,
    EpisodeMemory,
    EpisodeNotFoundError,
    EpisodeStateError,
    InvalidInputError,
)
from ontologies.vocab import (
    EPISODES,
    EPISODIC,
    HAPPENED_DURING,
    PROV_QUALIFIED_ASSOCIATION,
    PROV_QUALIFIED_USAGE,
    PROV_STARTED_AT_TIME,
    XSD_DATETIME,
    engram,
)
from tests.episodes.conftest import NOW, learn_scene_classes, store_experienced_scene

BEGIN = "2026-01-26T15:30:00+01:00"


def babbling(memory: EpisodeMemory, **overrides: object) -> str:
    arguments = [ArgumentSpec("agent", "HyungJin"), ArgumentSpec("object", "left hand")]
    options: dict = {"activity_type": "action", "arguments": arguments, "begin": BEGIN}
    options.update(overrides)
    return memory.begin("babbling", **options).id


def test_begin_and_end_store_zone_aware_times_name_type_and_role_labelled_arguments(
    memory: EpisodeMemory,
) -> None:
    episode_id = babbling(memory)
    ended = memory.end(episode_id, end="2026-01-26T15:31:30+01:00")
    assert ended.activity == "babbling" and ended.activity_type == "action"
    assert ended.begin == dt.datetime.fromisoformat(BEGIN)
    assert ended.begin.utcoffset() == dt.timedelta(hours=1)
    assert ended.end is not None and (ended.end - ended.begin).total_seconds() == 90
    assert {(a.role, a.value, a.kind) for a in ended.arguments} == {
        ("agent", "HyungJin", "agent"),
        ("object", "left hand", "entity"),
    }
    episode = engram("x")  # the stored time literal keeps its zone and type
    episode = next(memory.store.quads(None, PROV_STARTED_AT_TIME, None, EPISODES)).object
    assert isinstance(episode, Literal) and episode.datatype == XSD_DATETIME
    assert episode.value.endswith("+01:00")


def test_agents_are_qualified_associations_and_objects_qualified_usages(
    memory: EpisodeMemory,
) -> None:
    episode_id = babbling(memory, arguments=[ArgumentSpec("helper", "Bob", kind="agent")])
    episode = memory.get(episode_id)
    subject = engram("unused")
    subject = next(memory.store.quads(None, PROV_QUALIFIED_ASSOCIATION, None, EPISODES)).subject
    assert subject.value == episode.iri
    assert list(memory.store.quads(None, PROV_QUALIFIED_USAGE, None, EPISODES)) == []
    assert episode.arguments[0].kind == "agent"


def test_begin_defaults_to_the_clock(memory: EpisodeMemory) -> None:
    assert memory.begin("say").begin == NOW


@pytest.mark.parametrize(
    ("options", "field", "fragment"),
    [
        ({"begin": "2026-01-26T15:30:00"}, "begin", "time zone"),
        ({"begin": "yesterday"}, "begin", "ISO 8601"),
        ({"begin": "2026-13-01T00:00:00Z"}, "begin", "ISO 8601"),
        ({"arguments": [ArgumentSpec("", "x")]}, "arguments[0].role", "non-empty"),
        ({"arguments": [ArgumentSpec("agent", " ")]}, "arguments[0].value", "non-empty"),
        ({"arguments": [ArgumentSpec("a", "x"), ArgumentSpec("a", "x")]}, "arguments[1]", "once"),
        ({"episode_id": "../etc"}, "id", "letters"),
        ({"activity_type": ""}, "type", "non-empty"),
    ],
)
def test_bad_begin_names_field_and_writes_nothing(
    memory: EpisodeMemory, options: dict, field: str, fragment: str
) -> None:
    before = len(memory.store)
    with pytest.raises(InvalidInputError) as caught:
        babbling(memory, **options)
    assert caught.value.field == field
    assert fragment in str(caught.value)
    assert len(memory.store) == before


def test_end_before_begin_and_ending_twice_are_refused(memory: EpisodeMemory) -> None:
    episode_id = babbling(memory)
    with pytest.raises(InvalidInputError) as caught:
        memory.end(episode_id, end="2026-01-26T15:29:59+01:00")
    assert caught.value.field == "end"
    memory.end(episode_id, end="2026-01-26T15:40:00+01:00")
    with pytest.raises(EpisodeStateError, match="already ended"):
        memory.end(episode_id, end="2026-01-26T15:50:00+01:00")
    with pytest.raises(EpisodeNotFoundError):
        memory.end("nope", end="2026-01-26T15:50:00+01:00")


def test_taken_id_is_refused(memory: EpisodeMemory) -> None:
    babbling(memory, episode_id="e1")
    with pytest.raises(EpisodeStateError, match="already exists"):
        babbling(memory, episode_id="e1")


def test_snapshots_record_the_scene_memory_at_begin_and_at_end(memory: EpisodeMemory) -> None:
    learn_scene_classes(memory.store, {"Scene-1": 0.5, "Scene-2": 0.9}, items=3)
    episode_id = babbling(memory)
    learn_scene_classes(memory.store, {"Scene-3": 1.2}, items=5)
    episode = memory.end(episode_id, end="2026-01-26T16:00:00+01:00")
    begin, end = episode.state_at_begin, episode.state_at_end
    assert begin is not None and end is not None
    assert (begin.learned_classes, begin.episodic_items) == (2, 3)
    assert [(c.cls.rsplit("#")[-1], c.score, c.rank) for c in begin.best_classes] == [
        ("Scene-2", 0.9, 1),
        ("Scene-1", 0.5, 2),
    ]
    assert (end.learned_classes, end.episodic_items) == (3, 5)
    assert end.best_classes[0].cls.endswith("Scene-3")


def test_empty_scene_memory_gives_a_zero_snapshot(memory: EpisodeMemory) -> None:
    state = memory.get(babbling(memory)).state_at_begin
    assert state is not None and (state.learned_classes, state.episodic_items) == (0, 0)
    assert state.best_classes == ()


def test_annotations_over_the_whole_episode_and_a_range_inside_it(memory: EpisodeMemory) -> None:
    episode_id = babbling(memory)
    memory.end(episode_id, end="2026-01-26T15:40:00+01:00")
    memory.annotate(episode_id, key="comment", value="went well")
    ranged = memory.annotate(
        episode_id,
        key="gesture",
        value="wave",
        author="gesture-recogniser",
        confidence=0.8,
        start="2026-01-26T15:32:00+01:00",
        end="2026-01-26T15:33:00+01:00",
    )
    annotations = memory.get(episode_id).annotations
    assert [(a.key, a.value) for a in annotations] == [
        ("comment", "went well"),
        ("gesture", "wave"),
    ]
    assert annotations[1] == ranged
    assert annotations[1].author == "gesture-recogniser" and annotations[1].confidence == 0.8
    assert annotations[0].created == NOW


@pytest.mark.parametrize(
    ("options", "field"),
    [
        ({"start": "2026-01-26T15:00:00+01:00"}, "start"),
        ({"end": "2026-01-26T15:41:00+01:00"}, "end"),
        ({"start": "2026-01-26T15:35:00+01:00", "end": "2026-01-26T15:34:00+01:00"}, "end"),
        ({"start": "15:35"}, "start"),
        ({"confidence": 1.5}, "confidence"),
        ({"confidence": True}, "confidence"),
        ({"key": ""}, "key"),
    ],
)
def test_bad_annotation_names_field_and_writes_nothing(
    memory: EpisodeMemory, options: dict, field: str
) -> None:
    episode_id = babbling(memory)
    memory.end(episode_id, end="2026-01-26T15:40:00+01:00")
    before = len(memory.store)
    arguments = {"key": "gesture", "value": "wave", **options}
    with pytest.raises(InvalidInputError) as caught:
        memory.annotate(episode_id, **arguments)
    assert caught.value.field == field
    assert len(memory.store) == before


def test_scene_items_link_to_their_episode(memory: EpisodeMemory) -> None:
    episode_id = babbling(memory)
    store_experienced_scene(memory.store, "scene-7")
    memory.link_scene(episode_id, engram("scene-7").value)
    assert memory.get(episode_id).scenes == (engram("scene-7").value,)
    assert len(list(memory.store.quads(engram("scene-7"), HAPPENED_DURING, None, EPISODIC))) == 1


def test_delete_removes_every_triple_of_the_episode_but_shared_participants_stay(
    memory: EpisodeMemory,
) -> None:
    keep = babbling(memory)
    store_experienced_scene(memory.store, "scene-1")
    before = memory.store.graph_sizes()
    gone = babbling(memory, arguments=[ArgumentSpec("agent", "HyungJin"), ArgumentSpec("x", "y")])
    memory.end(gone, end="2026-01-26T15:40:00+01:00")
    memory.annotate(gone, key="k", value="v", author="someone")
    run = memory.runs.start(gone, name="edges", producer="canny", parameters={"sigma": 1})
    memory.ratings.rate(gone, run.id, person="Alice", value=7)
    memory.link_scene(gone, engram("scene-1").value)
    memory.delete(gone)
    assert memory.store.graph_sizes() == before
    assert memory.get(keep).arguments[0].value == "HyungJin"
    with pytest.raises(EpisodeNotFoundError):
        memory.get(gone)
    with pytest.raises(EpisodeNotFoundError):
        memory.delete(gone)
