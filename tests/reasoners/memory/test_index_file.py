"""The index file beside the store: opening reads it when it is current, and rebuilds the model
from the triples when it is missing, stale, truncated, corrupt or half-written."""

import dataclasses
import gc
import itertools
import os
import random
import shutil
import signal
import subprocess
import sys
import threading
from collections.abc import Callable
from pathlib import Path

import numpy as np
import pytest
from pyoxigraph import Literal

from kg import Store
from ontologies.vocab import MEMORY, PLANE, RDFS_LABEL, SPHERE, engram
from reasoners import forgetting, index_file, persist
from reasoners.errors import MemoryLoadingError
from reasoners.index import SignatureIndex
from reasoners.memory import SceneMemory
from reasoners.model import MemoryModel
from reasoners.signature import Signature, _frozenset_hashes

from .conftest import FakeClock, plane, sphere
from .index_writer import scenes

ROOT = Path(__file__).resolve().parents[3]


def assert_same_model(opened: MemoryModel, built: MemoryModel) -> None:
    """Every public field of the model's parts (new ones included), the index and the live
    scores."""
    parts = ("graph", "scores", "items", "state", "trash")
    assert set(vars(opened)) == set(vars(built)) == set(parts)
    for part in parts:
        mine, theirs = getattr(opened, part), getattr(built, part)
        for field in dataclasses.fields(mine):
            # the history epoch is read from the store by the first write (a view repaired on
            # open); the fields not compared are other parts, or the graph's shared with them
            name = field.name
            if (
                field.compare
                and not name.startswith("_")
                and name not in ("index", "history_epoch")
            ):
                assert getattr(mine, name) == getattr(theirs, name), f"{part}.{name}"
    assert opened.graph.index.classes() == built.graph.index.classes()
    assert opened.graph.index._at_least == built.graph.index._at_least
    assert opened.scores.zetas() == built.scores.zetas()
    assert opened.scores.max_score == built.scores.max_score


def filled(directory: Path, clock: FakeClock) -> SceneMemory:
    """A memory on disk with ten stored scenes (four classes), a retrieval and a pin."""
    memory = SceneMemory(Store(directory), clock=clock)
    for scene in scenes():
        memory.store_scene(scene)
        clock.advance(minutes=5)
    memory.retrieve([("Sphere", "isAboveOf", "Plane")])
    memory.pin(memory.reads.classes()[0].iri)
    return memory


@pytest.fixture(scope="module")
def saved_memory_dir(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A closed store holding :func:`filled`'s memory, with its index file saved."""
    directory = tmp_path_factory.mktemp("saved") / "store"
    memory = filled(directory, FakeClock())
    assert memory.save_index()
    memory.store.flush()
    del memory
    gc.collect()
    return directory


@pytest.fixture
def saved_copy(saved_memory_dir: Path, tmp_path: Path) -> Path:
    """A copy of :func:`saved_memory_dir` (store and index file) in ``tmp_path``."""
    shutil.copytree(saved_memory_dir, tmp_path / "store")
    name = saved_memory_dir.name + index_file.SUFFIX
    shutil.copy(saved_memory_dir.with_name(name), tmp_path / name)
    return tmp_path / "store"


def reopen(directory: Path, clock: FakeClock) -> SceneMemory:
    """Open the memory again (the caller has dropped the one that had the store open)."""
    gc.collect()  # closes the store, which one process at a time may open
    return SceneMemory(Store(directory), clock=clock)


def test_a_saved_memory_opens_from_its_index_file_equal_to_the_rebuilt_one(
    tmp_path: Path, clock: FakeClock
) -> None:
    memory = filled(tmp_path / "store", clock)
    assert memory.save_index()
    assert not memory.save_index()  # nothing changed since
    del memory
    opened = reopen(tmp_path / "store", clock)
    assert opened.loaded.source == "index file"
    assert_same_model(opened.loaded.model, persist.load_model(opened.store))
    # and it goes on working: the next scene is recognised as before
    result = opened.store_scene(scenes()[3])
    assert not result.learned


def test_every_committed_transaction_changes_the_revision_and_a_failed_one_does_not(
    tmp_path: Path, clock: FakeClock
) -> None:
    memory = SceneMemory(Store(tmp_path / "store"), clock=clock)
    seen = {index_file.stored_revision(memory.store)}
    for scene in scenes()[:3]:
        memory.store_scene(scene)
        seen.add(index_file.stored_revision(memory.store))
    assert None in seen and len(seen) == 4
    before = index_file.stored_revision(memory.store)
    with pytest.raises(ValueError, match="the caller failed"), memory.transactions.write() as tx:
        tx.insert(memory.reads.classes()[0].iri, RDFS_LABEL, Literal("x"), MEMORY)
        raise ValueError("the caller failed")
    assert index_file.stored_revision(memory.store) == before


def test_an_index_file_older_than_the_store_is_detected_and_rebuilt(
    tmp_path: Path, clock: FakeClock
) -> None:
    memory = filled(tmp_path / "store", clock)
    memory.save_index()
    learned = len(memory.reads.classes())
    new = memory.store_scene([sphere("a", 0.0, 0.0, 0.5), plane("b", 0.0, 0.0, 0.0)])  # unsaved
    assert new.learned
    del memory
    opened = reopen(tmp_path / "store", clock)
    assert opened.loaded.source == "store"
    assert_same_model(opened.loaded.model, persist.load_model(opened.store))
    assert len(opened.reads.classes()) == learned + 1


def _truncate(path: Path) -> None:
    path.write_bytes(path.read_bytes()[:-100])


def _flip(path: Path) -> None:
    data = bytearray(path.read_bytes())
    data[len(data) // 2] ^= 0xFF
    path.write_bytes(bytes(data))


def _header_only(path: Path) -> None:
    path.write_bytes(path.read_bytes()[:40])


def _garbage(path: Path) -> None:
    path.write_bytes(b"not an index file at all")


def _a_global(path: Path) -> None:
    """A well-formed file whose payload would call a function when unpickled."""
    values = index_file.read(path)
    values["classes"] = os.system  # pickled as a global reference
    index_file.write_snapshot(path, values)


def _wrong_shape(path: Path) -> None:
    values = index_file.read(path)
    values["classes"] = [("only an IRI",)]
    index_file.write_snapshot(path, values)


def _zero_count(path: Path) -> None:
    """A well-formed file (checksum and all) whose signatures hold a count of 0."""
    values = index_file.read(path)
    columns = list(values["classes"])
    columns[3] = bytes(len(columns[3]))  # the packed counts, every one 0
    values["classes"] = tuple(columns)
    index_file.write_snapshot(path, values)


def _empty(path: Path) -> None:
    path.write_bytes(b"")


@pytest.mark.parametrize(
    "damage",
    [_truncate, _flip, _header_only, _garbage, _a_global, _wrong_shape, _zero_count, _empty],
)
def test_a_damaged_index_file_falls_back_to_the_store(
    saved_copy: Path, clock: FakeClock, damage: Callable[[Path], None]
) -> None:
    assert reopen(saved_copy, clock).loaded.source == "index file"  # undamaged
    damage(saved_copy.with_name(saved_copy.name + index_file.SUFFIX))
    opened = reopen(saved_copy, clock)
    assert opened.loaded.source == "store"
    assert_same_model(opened.loaded.model, persist.load_model(opened.store))


def test_an_index_file_written_for_other_weights_is_not_used(saved_copy: Path) -> None:
    gc.collect()
    store = Store(saved_copy)
    path = index_file.index_path(store)
    assert path is not None
    revision = index_file.stored_revision(store)
    assert index_file.load(path, revision, (0.25, 0.15, 0.3, 0.3)) is None
    assert index_file.load(path, revision, (0.2, 0.2, 0.3, 0.3)) is not None


def test_the_payload_holds_built_in_values_only(saved_copy: Path) -> None:
    path = saved_copy.with_name(saved_copy.name + index_file.SUFFIX)
    _a_global(path)
    with pytest.raises(index_file.IndexFileError, match=r"global posix\.system refused"):
        index_file.read(path)


@pytest.mark.slow
@pytest.mark.parametrize("mode", ["mid-write", "before-rename"])
def test_a_process_killed_while_saving_leaves_a_memory_that_opens_correctly(
    tmp_path: Path, clock: FakeClock, mode: str
) -> None:
    directory = tmp_path / "store"
    with subprocess.Popen(
        [sys.executable, "-m", "tests.reasoners.memory.index_writer", str(directory), mode],
        cwd=ROOT,
        env={**os.environ, "PYTHONPATH": str(ROOT)},
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
    ) as writer:
        assert writer.stdout is not None
        line = writer.stdout.readline()
        writer.send_signal(signal.SIGKILL)
        _, errors = writer.communicate()
    assert line == b"SAVING\n", errors.decode()
    leftovers = list(tmp_path.glob("store.memory-index.*.tmp"))
    assert len(leftovers) == 1  # the kill happened inside the save
    opened = SceneMemory(Store(directory), clock=clock)
    assert opened.loaded.source == "store"  # the complete file is one scene behind
    assert_same_model(opened.loaded.model, persist.load_model(opened.store))
    assert len(opened.reads.items()) == 10  # the scene stored after the complete save is there
    assert opened.save_index()
    assert not list(tmp_path.glob("store.memory-index.*.tmp"))
    del opened
    again = reopen(directory, clock)
    assert again.loaded.source == "index file"
    assert_same_model(again.loaded.model, persist.load_model(again.store))


def test_a_memory_opening_in_the_background_answers_loading_until_it_is_ready(
    tmp_path: Path, clock: FakeClock, monkeypatch: pytest.MonkeyPatch
) -> None:
    memory = filled(tmp_path / "store", clock)
    del memory
    gc.collect()
    release = threading.Event()
    real = index_file.open_model

    def slow_open(*args: object, **kwargs: object) -> object:
        release.wait(10)
        return real(*args, **kwargs)  # type: ignore[arg-type]

    monkeypatch.setattr(index_file, "open_model", slow_open)
    monkeypatch.setattr("reasoners.loading.LOADING_WAIT_S", 0.0)
    opening = SceneMemory(Store(tmp_path / "store"), clock=clock, background=True)
    assert not opening.loaded.ready and opening.loaded.source == ""
    with pytest.raises(MemoryLoadingError, match="still loading"):
        opening.store_scene(scenes()[0])
    with pytest.raises(MemoryLoadingError):
        opening.reads.classes()
    release.set()
    assert opening.loaded.wait_ready(10)
    assert opening.loaded.source == "store"
    assert len(opening.reads.items()) == 10
    assert not opening.store_scene(scenes()[0]).learned


def test_a_memory_that_fails_to_open_in_the_background_says_why(
    tmp_path: Path, clock: FakeClock, monkeypatch: pytest.MonkeyPatch
) -> None:
    def broken(*args: object, **kwargs: object) -> object:
        raise OSError("disk on fire")

    monkeypatch.setattr(index_file, "open_model", broken)
    opening = SceneMemory(Store(tmp_path / "store"), clock=clock, background=True)
    assert not opening.loaded.wait_ready(10)
    with pytest.raises(MemoryLoadingError, match="disk on fire"):
        opening.reads.classes()


def test_opening_from_the_index_file_writes_nothing_and_keeps_the_file_current(
    saved_copy: Path, clock: FakeClock
) -> None:
    path = saved_copy.with_name(saved_copy.name + index_file.SUFFIX)
    saved = index_file.read(path)["revision"]
    opened = reopen(saved_copy, clock)
    assert opened.loaded.source == "index file"
    # the score view the file says the store holds is taken as written: no repair transaction
    assert index_file.stored_revision(opened.store) == saved
    assert not opened.loaded.model.scores.unwritten
    assert not opened.save_index()  # still current
    del opened
    assert reopen(saved_copy, clock).loaded.source == "index file"


def test_an_index_file_after_a_forgotten_class_holds_the_index_without_its_hole(
    tmp_path: Path, clock: FakeClock
) -> None:
    memory = filled(tmp_path / "store", clock)
    first = memory.reads.classes()[0].iri
    with memory.transactions.write() as tx:  # a class leaves the index: its position becomes a hole
        forgetting.move_to_trash(
            tx, memory.loaded.model, memory.transactions.reader, [first], [], memory._now()
        )
    assert None in memory.loaded.model.graph.index.slots()
    assert memory.save_index()
    del memory
    opened = reopen(tmp_path / "store", clock)
    assert opened.loaded.source == "index file"
    assert_same_model(opened.loaded.model, persist.load_model(opened.store))


def test_the_saved_bitsets_of_an_index_with_holes_are_those_of_its_live_classes() -> None:
    above, below = engram("sphereIsAboveOf"), engram("planeIsBelowOf")
    entries = [
        (engram(f"Scene-{k}"), Signature(counts))
        for k, counts in enumerate(
            [{(above, PLANE): 1}, {(above, PLANE): 3, (below, SPHERE): 1}, {(above, PLANE): 2}]
        )
    ]
    index = SignatureIndex()
    index.add_all(entries)
    index.remove(entries[1][0])  # the only class with a count of 3, and with ``below``
    fresh = SignatureIndex()
    fresh.add_all([entries[0], entries[2]])
    assert index.state() == fresh.state()
    assert index.state()[0] == {(above, PLANE): [0, 0b11, 0b10]}


def test_signatures_read_in_bulk_hash_as_python_hashes_them() -> None:
    rng = random.Random(5)
    properties = [engram(name) for name in ("sphereIsAboveOf", "planeIsBelowOf", "isNear")]
    pool = [((p, t), n) for p in properties for t in (PLANE, SPHERE) for n in range(1, 4)]
    samples = [dict(rng.sample(pool, rng.randint(1, 6))) for _ in range(500)]
    runs = [dict(Signature(sample).items()) for sample in samples]  # in signature order
    keys = [key for run in runs for key in run]
    counts = [n for run in runs for n in run.values()]
    ends = list(itertools.accumulate(len(run) for run in runs))
    item_hashes = np.array([hash(item) for run in runs for item in run.items()], dtype=np.int64)
    python = [hash(frozenset(run.items())) for run in runs]
    assert _frozenset_hashes(item_hashes, ends) == python  # the bulk path, not its fallback
    built = Signature.unchecked_runs(keys, counts, ends, item_hashes)
    assert built == [Signature(run) for run in runs]
    assert [hash(s) for s in built] == python
    # wrong item hashes (another interpreter's frozenset hash) are caught and not used
    wrong = Signature.unchecked_runs(keys, counts, ends, item_hashes + 1)
    assert [hash(s) for s in wrong] == python
