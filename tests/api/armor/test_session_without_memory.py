"""A session built without the memory directives' adapter answers every directive that needs
the scene memory with ARMOR's memory error (212) naming the directive, and queues nothing."""

import pytest

from api.armor.context import Context
from api.armor.errors import MEMORY_ERROR, MemoryDirectiveError
from api.armor.memory import MEMORY_COMMANDS
from api.armor.references import Registry
from api.armor.session import Session
from api.protocol import ArmorDirectiveReq
from kg import Store

NEEDS_MEMORY = [
    ("SCENE_UPDATED_", []),
    ("RETRIEVE_SCENE_", ["Cube above Plane"]),
    ("RETRIEVE_SCENE_SPREAD", ["Cube above Plane"]),
    ("MEMORY_SLEEP_", []),
    ("MEMORY_PIN_", ["Cube"]),
    ("MEMORY_UNPIN_", ["Cube"]),
    ("MEMORY_RESTORE_", ["Cube"]),
    ("QUERY_MEMORY_SCORES", ["Cube"]),
    ("QUERY_MEMORY_LEVEL", ["Cube"]),
    ("QUERY_MEMORY_EXPLAIN", ["Cube"]),
    ("MEMORY_CLOCK_SET", ["2026-01-01T09:00:00+00:00"]),
    ("MEMORY_CLOCK_ADVANCE", ["60"]),
    ("QUERY_MEMORY_CLOCK", []),
]


def _context(session: Session, key: str, args: list[str]) -> Context:
    command, spec, *rest = key.split("_")
    request = ArmorDirectiveReq(
        client_name="c",
        reference_name="r",
        command=command,
        primary_command_spec=spec,
        secondary_command_spec="_".join(rest),
        args=args,
    )
    return Context(session=session, request=request, key=key, signature=MEMORY_COMMANDS[key][1])


def test_the_table_covers_every_memory_directive_but_load_init() -> None:
    assert {key for key, _ in NEEDS_MEMORY} == set(MEMORY_COMMANDS) - {"LOAD_INIT_"}


@pytest.mark.parametrize(("key", "args"), NEEDS_MEMORY)
def test_a_directive_that_needs_the_memory_answers_212_without_one(
    key: str, args: list[str]
) -> None:
    store = Store()
    session = Session(store, Registry(store))
    load_init = MEMORY_COMMANDS["LOAD_INIT_"][0]
    load_init(_context(session, "LOAD_INIT_", []))  # an open scene, for SCENE UPDATED
    with pytest.raises(MemoryDirectiveError, match="has no scene memory") as raised:
        MEMORY_COMMANDS[key][0](_context(session, key, args))
    assert raised.value.exit_code == MEMORY_ERROR
    assert str(raised.value).startswith(key.replace("_", " ").strip())
    assert session.queued == []
