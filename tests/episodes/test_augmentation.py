"""A-posteriori augmentation: versioned runs, derived samples linked to frames, what is lacking;
feedback: ratings and the paper's ranking."""

import pytest
from pyoxigraph import NamedNode
from scipy.stats import wilcoxon

from episodes import (
    ArgumentSpec,
    DerivedSpec,
    EpisodeMemory,
    EpisodeStateError,
    InvalidInputError,
    NotFoundError,
)
from episodes.feedback import candidate_stats
from ontologies.vocab import EPISODES, FRAME_NUMBER, PROV_WAS_DERIVED_FROM
from tests.episodes.conftest import record_frames


@pytest.fixture
def three_babblings(disk_memory: EpisodeMemory) -> EpisodeMemory:
    """Three babbling episodes; b1 recorded 20 frames (1-20) of the camera "left"."""
    memory = disk_memory
    for i, day in enumerate(("01", "02", "03")):
        memory.begin(
            "babbling",
            arguments=[ArgumentSpec("agent", "iCub")],
            begin=f"2026-01-{day}T10:00:00+00:00",
            episode_id=f"b{i + 1}",
            record=i == 0,
        )
        if i == 0:
            record_frames(memory, "b1", {"left": range(1, 21)})
        memory.end(f"b{i + 1}", end=f"2026-01-{day}T10:10:00+00:00")
    memory.begin("point", begin="2026-01-04T10:00:00+00:00", episode_id="p1")
    return memory


def test_runs_are_versioned_per_episode_and_augmentation(three_babblings: EpisodeMemory) -> None:
    m = three_babblings
    first = m.runs.start("b1", name="kinematic_structure", producer="ks", parameters={"k": 3})
    second = m.runs.start("b1", name="kinematic_structure", producer="ks", parameters={"k": 4})
    other = m.runs.start("b1", name="edges", producer="canny")
    elsewhere = m.runs.start("b2", name="kinematic_structure", producer="ks")
    assert (first.version, second.version, other.version, elsewhere.version) == (1, 2, 1, 1)
    runs = m.runs.of_episode("b1")
    assert [(r.name, r.version, r.parameters) for r in runs] == [
        ("edges", 1, {}),
        ("kinematic_structure", 1, {"k": 3}),
        ("kinematic_structure", 2, {"k": 4}),
    ]
    assert runs[1].producer == "ks" and runs[1].started is not None


def test_which_episodes_lack_an_augmentation_is_one_query(three_babblings: EpisodeMemory) -> None:
    m = three_babblings
    m.runs.start("b1", name="kinematic_structure", producer="ks")
    m.runs.start("b1", name="kinematic_structure", producer="ks")
    m.runs.start("b2", name="kinematic_structure", producer="ks")
    m.runs.start("b3", name="edges", producer="canny")
    seen: list[str] = []
    with m.store.tracing(lambda kind, text, bindings: seen.append(kind)):
        lacking = m.runs.lacking("babbling", "kinematic_structure")
    assert [(e.id, runs) for e, runs in lacking] == [("b3", 0)]
    assert seen.count("query") == 1
    assert [
        (e.id, n) for e, n in m.runs.lacking("babbling", "kinematic_structure", versions=2)
    ] == [
        ("b2", 1),
        ("b3", 0),
    ]


def test_derived_samples_are_derived_from_their_source_frames(
    three_babblings: EpisodeMemory,
) -> None:
    m = three_babblings
    run = m.runs.start("b1", name="edges", producer="canny")
    added = m.runs.add_derived(
        "b1",
        run.id,
        [DerivedSpec(12, "/left", "/left/edges"), DerivedSpec(13, "/left", "/left/edges")],
    )
    assert [s.frame for s in added] == [12, 13]
    derived_from = list(m.store.quads(None, PROV_WAS_DERIVED_FROM, None, EPISODES))
    frames = {q.object for q in derived_from}
    assert len(derived_from) == 2
    numbers = {
        int(q.object.value)
        for frame in frames
        for q in m.store.quads(
            frame if isinstance(frame, NamedNode) else None, FRAME_NUMBER, None, EPISODES
        )
    }
    assert numbers == {12, 13}
    assert m.runs.of_episode("b1")[0].samples == 2


@pytest.mark.parametrize(
    ("spec", "field"),
    [
        (DerivedSpec(-1, "/left", "/left/edges"), "samples[0].frame"),
        (DerivedSpec(1, "", "/left/edges"), "samples[0].source_channel"),
        (DerivedSpec(1, "/left", ""), "samples[0].derived_channel"),
    ],
)
def test_bad_derived_sample_names_field_and_writes_nothing(
    three_babblings: EpisodeMemory, spec: DerivedSpec, field: str
) -> None:
    run = three_babblings.runs.start("b1", name="edges", producer="canny")
    before = len(three_babblings.store)
    with pytest.raises(InvalidInputError) as caught:
        three_babblings.runs.add_derived("b1", run.id, [DerivedSpec(1, "/left", "/x"), spec])
    assert caught.value.field == field.replace("[0]", "[1]")
    assert len(three_babblings.store) == before


def test_an_ended_run_takes_no_more_samples(three_babblings: EpisodeMemory) -> None:
    run = three_babblings.runs.start("b1", name="edges", producer="canny")
    ended = three_babblings.runs.end("b1", run.id)
    assert ended.ended is not None
    with pytest.raises(EpisodeStateError):
        three_babblings.runs.add_derived("b1", run.id, [DerivedSpec(1, "/left", "/left/edges")])
    with pytest.raises(NotFoundError):
        three_babblings.runs.end("b1", "0123abcd")


@pytest.mark.parametrize(
    ("options", "field"),
    [
        ({"value": 0}, "value"),
        ({"value": 11}, "value"),
        ({"value": 7.5}, "value"),
        ({"value": 7, "person": ""}, "person"),
        ({"value": 7, "time": "noon"}, "time"),
    ],
)
def test_bad_rating_names_field(three_babblings: EpisodeMemory, options: dict, field: str) -> None:
    run = three_babblings.runs.start("b1", name="edges", producer="canny")
    with pytest.raises(InvalidInputError) as caught:
        three_babblings.ratings.rate("b1", run.id, **{"person": "Alice", **options})
    assert caught.value.field == field


# The paper's day four: structures n (Q1 6, median 8) and p (Q1 6, median 7) pass the heuristic
# and are equivalent by Wilcoxon; d (Q1 4, median 4) does not pass.
RATERS = ["A", "B", "C", "D", "E"]
SCORES = {"n": [6, 6, 8, 8, 9], "p": [6, 7, 7, 6, 8], "d": [3, 4, 4, 4, 5]}


@pytest.fixture
def rated(three_babblings: EpisodeMemory) -> tuple[EpisodeMemory, dict[str, str]]:
    m = three_babblings
    ids = {}
    for label, scores in SCORES.items():
        run = m.runs.start(
            "b1", name="kinematic_structure", producer="ks", parameters={"label": label}
        )
        ids[label] = f"b1/{run.id}"
        for person, value in zip(RATERS, scores, strict=True):
            m.ratings.rate("b1", run.id, person=person, value=value)
    return m, ids


def test_ranking_applies_the_quartile_heuristic_and_wilcoxon(
    rated: tuple[EpisodeMemory, dict[str, str]],
) -> None:
    memory, ids = rated
    ranking = memory.ratings.rank("kinematic_structure")
    by_item = {c.item: c for c in ranking.candidates}
    assert (by_item[ids["n"]].q1, by_item[ids["n"]].median) == (6.0, 8.0)
    assert (by_item[ids["p"]].q1, by_item[ids["p"]].median) == (6.0, 7.0)
    assert not by_item[ids["d"]].good
    assert [c.item for c in ranking.candidates] == [ids["n"], ids["p"], ids["d"]]
    assert ranking.leader == ids["n"]
    expected_p = wilcoxon(SCORES["n"], SCORES["p"]).pvalue
    (comparison,) = ranking.comparisons
    assert comparison.p_value == pytest.approx(expected_p)
    assert comparison.equivalent and ranking.best == (ids["n"], ids["p"])


def test_a_revised_rating_of_a_person_counts(rated: tuple[EpisodeMemory, dict[str, str]]) -> None:
    memory, ids = rated
    run_id = ids["p"].split("/")[1]
    for person in RATERS:
        memory.ratings.rate(
            "b1", run_id, person=person, value=2, time="2026-02-27T00:00:00+00:00", replace=True
        )
    ranking = memory.ratings.rank("kinematic_structure")
    assert ranking.best == (ids["n"],)
    assert ranking.comparisons == ()


def test_no_candidate_good_enough_keeps_a_leader_but_no_best(
    three_babblings: EpisodeMemory,
) -> None:
    run = three_babblings.runs.start("b1", name="edges", producer="canny")
    for person, value in zip(RATERS, [4, 4, 5, 3, 4], strict=True):
        three_babblings.ratings.rate("b1", run.id, person=person, value=value)
    ranking = three_babblings.ratings.rank("edges")
    assert ranking.leader == f"b1/{run.id}" and ranking.best == ()


def test_identical_ratings_are_equivalent_without_a_scipy_warning() -> None:
    from episodes.feedback import compare

    a = candidate_stats("a", {"x": 8, "y": 7, "z": 9})
    b = candidate_stats("b", {"x": 8, "y": 7, "z": 9})
    assert compare(a, b, 0.05).p_value == 1.0


def test_rank_of_an_unrated_augmentation_is_empty(three_babblings: EpisodeMemory) -> None:
    ranking = three_babblings.ratings.rank("nothing")
    assert ranking.candidates == () and ranking.leader is None
