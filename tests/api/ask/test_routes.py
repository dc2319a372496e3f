"""``POST /ask``, ``POST /ask/audio``, ``GET /explain``, ``QUERY MEMORY EXPLAIN`` and
``engram ask`` on the lived week, through a live server and the command line."""

import base64
import json
import shlex
from collections.abc import Callable
from pathlib import Path

import pytest
from typer.testing import CliRunner

from api.ask.speech import synthesise
from api.cli import app
from ontologies.vocab import engram
from tests.conftest import LiveServer

pytestmark = pytest.mark.slow  # a live server


@pytest.fixture
def server(lived_server: LiveServer) -> LiveServer:
    return lived_server


def test_ask_answers_in_words_json_and_sparql(server: LiveServer) -> None:
    response = server.client.post(
        "/ask", json={"text": "How many times did Anna do motor babbling?"}
    )
    assert response.status_code == 200
    body = response.json()
    assert body["understood"] and body["form"] == "episode_count"
    assert body["words"] == "Anna did motor babbling twice."
    assert body["answer"] == {"count": 2}
    assert any("COUNT(DISTINCT ?episode)" in q for q in body["sparql"])


def test_ask_outside_the_grammar(server: LiveServer) -> None:
    body = server.client.post("/ask", json={"text": "sing me a song"}).json()
    assert body["understood"] is False and len(body["suggestions"]) == 3
    assert body["words"].startswith("I did not understand.")


@pytest.mark.parametrize(
    ("body", "field"),
    [({}, "text"), ({"text": ""}, "text"), ({"text": "x" * 501}, "text"), ({"text": 3}, "text")],
)
def test_ask_refuses_bad_bodies(server: LiveServer, body: object, field: str) -> None:
    response = server.client.post("/ask", json=body)
    assert response.status_code == 422
    assert field in json.dumps(response.json())


def test_ask_needs_the_token_when_one_is_set(
    start_server: Callable[..., LiveServer], lived_data_dir: Path
) -> None:
    server = start_server(data_dir=lived_data_dir, token="secret")
    assert server.client.post("/ask", json={"text": "what do you remember best"}).status_code == 401
    answer = server.client.post(
        "/ask",
        json={"text": "what do you remember best"},
        headers={"Authorization": "Bearer secret"},
    )
    assert answer.status_code == 200 and answer.json()["form"] == "scene_best"
    assert server.client.get("/explain", params={"about": "Scene-1"}).status_code == 200


def test_explain_a_class_a_forgotten_one_and_an_unknown_one(server: LiveServer) -> None:
    live = server.client.get("/explain", params={"about": "Scene-1"}).json()
    assert live["about"] == engram("Scene-1").value
    assert [e["kind"] for e in live["explanations"]] == ["learning", "placement", "level"]
    gone = server.client.get("/explain", params={"about": engram("Scene-2").value}).json()
    assert [e["kind"] for e in gone["explanations"]] == ["forgetting", "restore"]
    assert gone["explanations"][0]["weak_passes"] == 3
    unknown = server.client.get("/explain", params={"about": "Scene-99"})
    assert unknown.status_code == 404 and "Scene-99" in unknown.json()["detail"]
    assert server.client.get("/explain", params={"about": "a b"}).status_code == 422
    assert server.client.get("/explain").status_code == 422


def test_ask_audio_hears_answers_and_speaks(server: LiveServer) -> None:
    wav = synthesise("why did you forget scene two")
    response = server.client.post("/ask/audio", content=wav)
    assert response.status_code == 200
    body = response.json()
    assert body["heard"] == "why did you forget scene two"
    assert body["form"] == "explain_forget" and body["words"].startswith("I forgot Scene-2")
    assert base64.b64decode(body["speech"])[:4] == b"RIFF"
    assert body["spoken"] == f"You asked: why did you forget scene two. {body['words']}"
    spoken = server.client.post("/ask/audio", params={"reply": "wav"}, content=wav)
    assert spoken.headers["content-type"] == "audio/wav" and spoken.content[:4] == b"RIFF"
    assert spoken.headers["x-engram-heard"] == "why did you forget scene two"
    assert len(spoken.content) > len(synthesise(body["words"]))  # the question echoed first


def test_ask_audio_refuses_what_is_not_a_wav(server: LiveServer) -> None:
    response = server.client.post("/ask/audio", content=b"hello")
    assert response.status_code == 422 and response.json()["field"] == "audio"


def test_the_explain_directive(server: LiveServer) -> None:
    def call(args: list[str]) -> dict[str, object]:
        request = {
            "client_name": "dialogue",
            "reference_name": "engram",
            "command": "QUERY",
            "primary_command_spec": "MEMORY",
            "secondary_command_spec": "EXPLAIN",
            "args": args,
        }
        response = server.client.post("/armor_interface_srv", json={"armor_request": request})
        assert response.status_code == 200
        return response.json()["armor_response"]  # type: ignore[no-any-return]

    answer = call(["Scene-2"])
    assert answer["success"] is True
    assert str(answer["queried_objects"][0]).startswith("I forgot Scene-2")  # type: ignore[index]
    pairs = {p["key"]: p["value"] for p in answer["sparql_queried_objects"]}  # type: ignore[attr-defined]
    assert set(pairs) == {"forgetting", "restore", "json"}
    assert [e["kind"] for e in json.loads(pairs["json"])] == ["forgetting", "restore"]
    unknown = call(["Scene-99"])
    assert unknown["success"] is False and unknown["exit_code"] == 212
    assert call([])["success"] is False


def test_engram_ask_on_the_data_directory(lived_data_dir: Path, tmp_path: Path) -> None:
    runner = CliRunner()
    result = runner.invoke(app, ["ask", "what did you forget", "--data", str(lived_data_dir)])
    assert result.exit_code == 0, result.output
    assert "So far I forgot Scene-2 and 1 experienced scene." in result.output
    assert "because: I forgot Scene-2" in result.output
    wav = tmp_path / "question.wav"
    wav.write_bytes(synthesise("how many times did anna do motor babbling"))
    answer = tmp_path / "answer.wav"
    spoken = runner.invoke(
        app,
        [
            "ask",
            "--audio",
            str(wav),
            "--json",
            "--wav-out",
            str(answer),
            "--data",
            str(lived_data_dir),
        ],
    )
    assert spoken.exit_code == 0, spoken.output
    body = json.loads(spoken.stdout)  # stderr names the memory opened
    assert body["heard"] == "how many times did anna do motor babbling"
    assert body["words"] == "Anna did motor babbling twice."
    assert answer.read_bytes()[:4] == b"RIFF"
    assert runner.invoke(app, ["ask", "--data", str(lived_data_dir)]).exit_code == 2


def test_the_readme_example_answers_as_shown(lived_data_dir: Path) -> None:
    readme = (Path(__file__).resolve().parents[3] / "README.md").read_text(encoding="utf-8")
    section = readme.split("## Asking the memory", 1)[1]
    block = section.split("```sh\n", 1)[1].split("```", 1)[0]
    command = next(line for line in block.splitlines() if line.startswith("engram ask"))
    expected = section.split("```text\n", 1)[1].split("```", 1)[0].strip()
    words = shlex.split(command, comments=True)
    assert words[:4] == ["engram", "ask", "--data", "./anna-week"]  # built by the line above
    result = CliRunner().invoke(app, [*words[1:2], "--data", str(lived_data_dir), *words[4:]])
    assert result.exit_code == 0, result.output
    assert result.stdout.strip() == expected  # stderr names the memory opened
