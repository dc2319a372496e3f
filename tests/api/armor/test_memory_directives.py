"""A scripted perception client sends ten scenes through LOAD INIT … SCENE UPDATED."""

from api.client import ArmorClient, ArmorServiceInternalError, ScenePrimitive
from tests.api.armor.conftest import Armor

TABLE = ScenePrimitive("table", "Plane", centre=(0.3, 0.1, 0.1), axis=(0, 0, 1), hessian=-0.1)


def _ball(name: str, x: float) -> ScenePrimitive:
    return ScenePrimitive(name, "Sphere", centre=(x, 0.3, 0.3), radius=0.05, colour=(1, 0, 0))


def _cup(name: str, x: float) -> ScenePrimitive:
    return ScenePrimitive(
        name, "Cylinder", centre=(x, 0.3, 0.2), axis=(0, 0, 1), radius=0.04, height=0.1
    )


def test_ten_scenes_learn_recognise_retrieve_sleep_and_pin(armor: Armor, ref: str) -> None:
    client = ArmorClient("camera", ref, base_url=armor.url)
    scenes = [
        [_ball("b1", 0.3), TABLE],
        [_ball("b1", 0.31), TABLE],  # the same arrangement: reinforced, not learned
        [_ball("b1", 0.3), _ball("b2", 0.5), TABLE],  # more specific: learned
        [_cup("c1", 0.3), TABLE],
        [_cup("c1", 0.32), TABLE],
        [_ball("b1", 0.3), _cup("c1", 0.6), TABLE],
        [_ball("b1", 0.3), TABLE],
        [_ball("b1", 0.3), _ball("b2", 0.5), TABLE],
        [_cup("c1", 0.3), _cup("c2", 0.6), TABLE],
        [_ball("b1", 0.3), TABLE],
    ]
    answers = [client.memory.store_scene(scene) for scene in scenes]
    learned = [a.details["learned"] == ["true"] for a in answers]
    assert learned == [True, False, True, True, False, True, False, False, True, False]
    first = answers[0].values[0]
    assert (
        answers[1].values == [first]
        and answers[6].values == [first]
        and answers[9].values == [first]
    )
    assert first in answers[2].details["recognised"][0] or any(
        first in r for r in answers[2].details["recognised"]
    )
    assert answers[2].details["parent"] == [first]
    scores = client.memory.scores(first)
    assert scores.details["store_count"] == ["4"]
    assert client.memory.level(first) in {"HIGH", "LOW", "WEAK"}
    recalled = client.memory.retrieve(["Sphere isAboveOf Plane"])
    assert recalled.values == [first]
    assert client.memory.scores(first).details["retrieve_count"] == ["1"]
    sleep = client.memory.sleep()
    assert sleep.details["rescored"] and int(sleep.details["rescored"][0]) >= 5
    client.memory.pin(first)
    assert client.memory.scores(first).details["pinned"] == ["true"]
    client.close()


def test_memory_directive_errors_and_rollback(armor: Armor, ref: str) -> None:
    def call(
        command: str, first: str = "", second: str = "", args: list[str] | None = None
    ) -> dict[str, object]:
        return armor.call(command, first, second, args, ref=ref, client="cam")

    assert call("SCENE", "UPDATED")["exit_code"] == 212  # no open scene
    assert call("LOAD", "INIT")["success"]
    assert call("LOAD", "INIT")["exit_code"] == 212  # already open
    assert call("ADD", "IND", "CLASS", ["x", "Cube"])["exit_code"] == 212
    assert call("ADD", "DATAPROP", "IND", ["weight", "x", "DOUBLE", "1"])["exit_code"] == 212
    call("ADD", "IND", "CLASS", ["lonely", "Sphere"])
    for axis, value in zip("XYZ", ("0.1", "0.2", "0.3"), strict=True):
        call("ADD", "DATAPROP", "IND", [f"centre{axis}", "lonely", "DOUBLE", value])
    alone = call("SCENE", "UPDATED")
    assert alone["exit_code"] == 212 and "relation" in str(alone["error_description"])
    # a list whose scene is fine but whose other directive fails stores nothing
    # and leaves no scene open
    client = ArmorClient("cam2", ref, base_url=armor.url)
    directives = [("LOAD", "INIT", "", [])]
    for primitive in (_ball("b", 0.3), TABLE):
        directives += primitive.directives()
    directives += [("SCENE", "UPDATED", "", []), ("ADD", "IND", "CLASS", ["only_one"])]
    result = client.call_list(directives)  # type: ignore[arg-type]
    assert result.success is False
    assert (
        client.call("SCENE", "UPDATED", "", []).exit_code == 212
    )  # the list's LOAD INIT was undone too
    try:
        client.memory.scores("Scene-999")
    except ArmorServiceInternalError as error:
        assert error.exit_code == 212
    else:
        raise AssertionError("scores of an unknown class must fail")
    client.close()
