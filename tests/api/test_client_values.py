"""The Python client beyond armor_py_api: answers as Python values, ``ask()``, errors that say
what was wrong with the input, and the sample point cloud it ships."""

import math
from collections.abc import Iterator
from typing import Any

import httpx
import pytest

from api.armor import ArmorEngine
from api.client import (
    ArmorClient,
    ArmorInputError,
    ArmorServiceInternalError,
    LocalTransport,
    Primitive,
    parse_value,
)
from api.perceive import perceive
from api.samples import BREAKFAST
from kg import Store, ensure_ontology
from reasoners.memory import SceneMemory
from shapes import Perception, open_source
from tests.conftest import LiveServer

ENGRAM = "https://w3id.org/engram/ontology#"
BALL = Primitive("ball", "Sphere", centre=(0.3, 0.3, 0.3), radius=0.05)
TABLE = Primitive("table", "Plane", centre=(0.3, 0.1, 0.1), axis=(0, 0, 1), hessian=-0.1)


@pytest.fixture
def local_client() -> Iterator[ArmorClient]:
    """A client of an engine in this process, over a fresh memory."""
    store = Store()
    ensure_ontology(store)
    engine = ArmorEngine(store, scene_memory=SceneMemory(store))
    http = httpx.Client(base_url="http://engram.local", transport=LocalTransport(engine))
    with ArmorClient("tests", "engram", http=http) as client:
        yield client


@pytest.mark.parametrize(
    ("text", "value"),
    [
        (f"<{ENGRAM}Scene-2>", "Scene-2"),
        ("<http://ex.org/things/cup>", "cup"),
        ("0.5", 0.5),
        ("-3", -3),
        ("1e-3", 0.001),
        ("true", True),
        ("false", False),
        ('"3"^^xsd:integer', 3),
        ('"0.25"^^<http://www.w3.org/2001/XMLSchema#double>', 0.25),
        ('"true"^^xsd:boolean', True),
        ('"blue"', "blue"),
        ('"a b"@en', "a b"),
        (f"<{ENGRAM}Scene-1> 0.87", ("Scene-1", 0.87)),
        ("HIGH", "HIGH"),
        ("nan", "nan"),
        ("2026-01-26T08:00:00+00:00", "2026-01-26T08:00:00+00:00"),
        ("", None),
    ],
)
def test_answer_strings_read_as_values(text: str, value: Any) -> None:
    assert parse_value(text) == value


def test_a_stored_scene_answers_names_and_numbers(local_client: ArmorClient) -> None:
    stored = local_client.memory.store_scene([BALL, TABLE])
    assert stored.values == [f"<{ENGRAM}Scene-1>"]  # armor_py_api's strings stay
    assert stored.typed_values == ["Scene-1"]
    assert stored.detail("learned") is True and stored.detail("complexity") == stored.detail(
        "complexity"
    )
    assert isinstance(stored.detail("complexity"), int)
    scores = local_client.memory.scores("Scene-1")
    assert scores.typed_values == [1.0] and scores.detail("pinned") is False
    assert isinstance(scores.detail("raw_score"), float)
    recalled = local_client.memory.retrieve(["Sphere isAboveOf Plane"])
    assert recalled.typed_values == ["Scene-1"]
    assert all(
        isinstance(name, str) and isinstance(similarity, float)
        for name, similarity in recalled.typed_details.get("similar", [])
    )


@pytest.mark.parametrize(
    ("cue", "fragment"),
    [
        (["Sphere isAboveOf"], "expected 'Type relation Type'"),
        (["Sphere isOnTopOf Plane"], "relation: got 'isOnTopOf', expected one of"),
    ],
)
def test_a_bad_cue_raises_an_input_error_saying_what(
    local_client: ArmorClient, cue: list[str], fragment: str
) -> None:
    with pytest.raises(ArmorInputError) as raised:
        local_client.memory.retrieve(cue)
    assert fragment in str(raised.value)
    assert not str(raised.value).startswith("ARMOR internal error")
    assert raised.value.exit_code == 212
    assert isinstance(raised.value, ValueError | ArmorServiceInternalError)


def test_a_scene_of_one_object_says_why_it_is_refused(local_client: ArmorClient) -> None:
    with pytest.raises(ArmorInputError, match="expected a scene of at least two related"):
        local_client.memory.store_scene([BALL])


@pytest.mark.parametrize(
    ("fields", "fragment"),
    [
        ({"kind": "Sphre"}, "kind: got 'Sphre', expected one of Sphere, Cylinder, Cone, Plane"),
        ({"centre": (0.0, 0.0)}, "centre: got (0.0, 0.0), expected three finite numbers"),
        ({"centre": (0.0, math.nan, 0.0)}, "centre: got nan, expected a finite number"),
        ({"radius": -0.05}, "radius: got -0.05, expected a positive length"),
        ({"id": " "}, "primitive id: got ' '"),
    ],
)
def test_a_bad_primitive_is_refused_before_anything_is_sent(
    fields: dict[str, Any], fragment: str
) -> None:
    given = {"id": "ball", "kind": "Sphere", "centre": (0.3, 0.3, 0.3), "radius": 0.05}
    with pytest.raises(ValueError) as raised:
        Primitive(**{**given, **fields})
    assert fragment in str(raised.value)


def test_ask_answers_in_words_with_names(live_server: LiveServer) -> None:
    with ArmorClient("tests", "engram", base_url=live_server.url) as client:
        client.memory.store_scene([BALL, TABLE])
        answer = client.ask("what do you remember best")
        assert answer.understood and "Scene-1" in answer.words
        assert answer.answer["best"][0][0] == "Scene-1"
        lost = client.ask("frobnicate the teapot")
        assert not lost.understood and lost.suggestions
        with pytest.raises(ValueError, match="expected a question in words"):
            client.ask("  ")


def test_the_sample_cloud_gives_a_first_scene(local_client: ArmorClient) -> None:
    assert BREAKFAST.is_file() and BREAKFAST.stat().st_size < 300_000
    (result,) = perceive(open_source(BREAKFAST), local_client, perception=Perception(seed=0))
    assert result.learned
    assert sorted(p.kind.value for p in result.scene.primitives) == ["Cylinder", "Sphere"]
