"""The README's episode section: its Python example prints what it says, its SPARQL answers
(issue 16: roles, arguments after the fact, world state at begin and end)."""

import re
from pathlib import Path
from typing import Any

import pytest

from api.client import ArmorClient, Primitive
from tests.conftest import LiveServer

README = (Path(__file__).resolve().parents[2] / "README.md").read_text(encoding="utf-8")
SECTION = README.split("## Episodes\n", 1)[1].split("\n## ", 1)[0]


def _blocks(language: str) -> list[str]:
    found = re.findall(r"^```(\w*)\n(.*?)^```$", SECTION, flags=re.DOTALL | re.MULTILINE)
    return [body for tag, body in found if tag == language]


def _sparql(client: Any, query: str) -> list[dict[str, str]]:
    answer = client.post(
        "/sparql", data={"query": query}, headers={"Accept": "application/sparql-results+json"}
    )
    assert answer.status_code == 200, answer.text
    rows = answer.json()["results"]["bindings"]
    return [{k: v["value"] for k, v in row.items()} for row in rows]


def test_the_python_example_prints_what_the_readme_says(
    live_server: LiveServer, capsys: pytest.CaptureFixture[str]
) -> None:
    (code,) = _blocks("python")
    exec(compile(code.replace("http://127.0.0.1:8000", live_server.url), "README", "exec"), {})
    assert capsys.readouterr().out.split() == ["{'count':", "1}", "p2", "g1"]
    count, _ = _blocks("sparql")
    assert _sparql(live_server.client, count) == [{"times": "1"}]


def _scene(*extra: Primitive) -> list[Primitive]:
    table = Primitive("table", "Plane", centre=(0.3, 0.1, 0.1), axis=(0, 0, 1), hessian=-0.1)
    ball = Primitive("ball", "Sphere", centre=(0.3, 0.3, 0.3), radius=0.05)
    return [ball, table, *extra]


def test_what_was_on_the_table_when_hyungjin_started_babbling(live_server: LiveServer) -> None:
    client = live_server.client
    armor = ArmorClient("camera", "scenes", base_url=live_server.url)
    armor.memory.store_scene(_scene())
    begun = client.post(
        "/episodes",
        json={
            "activity": "babbling",
            "id": "b1",
            "arguments": [{"role": "agent", "value": "HyungJin"}],
        },
    )
    assert begun.status_code == 201
    cup = Primitive(
        "cup", "Cylinder", centre=(0.6, 0.3, 0.2), axis=(0, 0, 1), radius=0.04, height=0.1
    )
    armor.memory.store_scene(_scene(cup))
    client.post("/episodes/b1/arguments", json={"role": "recipient", "value": "iCub"})
    assert client.post("/episodes/b1/end", json={}).status_code == 200
    armor.close()
    _, on_the_table = _blocks("sparql")
    rows = _sparql(client, on_the_table)
    assert sorted((r["object"], r["kind"].rsplit("#", 1)[1]) for r in rows) == [
        ("ball", "Sphere"),
        ("table", "Plane"),
    ]
    assert len({r["sceneClass"] for r in rows}) == 1
    world = client.get("/episodes/b1/world").json()
    assert [o["label"] for o in world["appeared"]] == ["cup"]
    assert sorted(o["label"] for o in world["stayed"]) == ["ball", "table"]
    assert world["joined"] == ["iCub"] and world["begin"]["participants"] == ["HyungJin"]
    assert world["begin"]["scene_class"] and world["end"]["scene"] != world["begin"]["scene"]
    assert client.get("/episodes/nope/world").status_code == 404
