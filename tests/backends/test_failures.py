"""The SPARQL server killed (SIGKILL) under a writing Engram: clear 503s while it is away, no
acknowledged write lost, and the scene memory's index back in step once it returns."""

from collections.abc import Callable
from pathlib import Path

import pytest

from api.client import ArmorClient, Primitive, primitive_directives
from tests.backends.servers import OxigraphServer
from tests.conftest import LiveServer

pytestmark = pytest.mark.slow

BALL = Primitive("ball", "Sphere", centre=(0.3, 0.3, 0.3), radius=0.05)
TABLE = Primitive("table", "Plane", centre=(0.3, 0.1, 0.1), axis=(0, 0, 1))


def test_a_killed_server_gets_503s_then_the_writer_catches_up_without_losing_a_write(
    tmp_path: Path, start_server: Callable[..., LiveServer]
) -> None:
    oxigraph = OxigraphServer(tmp_path / "db").start()
    try:
        robot = start_server(store_url=oxigraph.url, memory="robot-a")
        with ArmorClient("camera", "engram", base_url=robot.url) as client:
            first = client.memory.store_scene([BALL, TABLE])  # acknowledged
            cls = first.values[0]
            oxigraph.kill()
            answer = robot.client.post(
                "/armor_interface_serialized_srv",
                json={"armor_requests": _scene_list()},
            )
            # ARMOR answers in its own protocol: the failing directive with the reason
            failed = answer.json()["armor_responses"][-1]
            assert not failed["success"] and "cannot be reached" in failed["error_description"]
            sparql = robot.client.get("/sparql", params={"query": "ASK { ?s ?p ?o }"})
            assert sparql.status_code == 503
            assert "cannot be reached" in sparql.json()["detail"]
            oxigraph.start()
            again = client.memory.store_scene([BALL, TABLE])
            assert again.values == [cls] and again.details["learned"] == ["false"]
            # the failed scene left nothing behind: one acknowledged + one now
            assert client.memory.scores(cls).details["store_count"] == ["2"]
    finally:
        oxigraph.stop()


def _scene_list() -> list[dict[str, object]]:
    directives = [("LOAD", "INIT", "", [])]
    directives += primitive_directives(BALL) + primitive_directives(TABLE)
    directives.append(("SCENE", "UPDATED", "", []))
    return [
        {
            "client_name": "camera",
            "reference_name": "engram",
            "command": c,
            "primary_command_spec": p,
            "secondary_command_spec": s,
            "args": a,
        }
        for c, p, s, a in directives
    ]
