"""The scene memory's in-memory model saved beside the store, so that opening reads one file.

Rebuilding the model from triples (:func:`reasoners.persist.load_model`) reads every learned
class, edge and experienced scene through SPARQL: seconds at 10,000 classes. The index file holds
the same facts as plain values (IRIs as strings, signatures as key numbers, times as ISO text),
so opening reads it and rebuilds the model with its bulk builder, and falls back to the triples
whenever the file cannot be trusted:

- **versioned**: every committed scene-memory transaction replaces the store's revision token
  (:func:`record_revision`, a random token in graph ``memory-revision``, committed with the
  transaction's other writes); the file names the token of the state it mirrors, and a file whose
  token is not the store's is stale (the store changed after it was written, or a backup was
  restored), as is one written for other score weights;
- **checked**: a header (magic, format number, payload length, SHA-256 of the payload) guards
  against truncation and corruption, and the payload is unpickled with every global refused, so
  it can only yield built-in values;
- **atomic**: written to a temporary file, fsynced, renamed over the old one and the directory
  fsynced; a process killed meanwhile leaves the old file (or none) and a temporary file that the
  next save removes.

The file is an accelerator, never the source of truth: nothing is lost without it.

>>> import tempfile
>>> from pathlib import Path
>>> from kg import Store
>>> from reasoners.model import MemoryModel
>>> store = Store(Path(tempfile.mkdtemp()) / "store")
>>> with store.transaction() as tx:
...     record_revision(tx, None, "r1")
>>> path = index_path(store)
>>> save(path, MemoryModel(), "r1")
>>> load(path, stored_revision(store), (0.2, 0.2, 0.3, 0.3)) is not None
True
>>> load(path, "r2", (0.2, 0.2, 0.3, 0.3)) is None   # stale
True
"""

import datetime as dt
import hashlib
import io
import logging
import os
import pickle
import struct
import uuid
from collections.abc import Callable
from pathlib import Path
from typing import Any

from pyoxigraph import Literal, NamedNode

from kg.store import Store
from kg.transaction import Transaction
from ontologies.vocab import MEMORY_REVISION, MEMORY_REVISION_GRAPH, MEMORY_STATE_INDIVIDUAL
from reasoners.model import (
    ClassRecord,
    Derived,
    ItemRecord,
    MemoryModel,
    TrashedClass,
    TrashedItem,
)
from reasoners.signature import Key, Signature

__all__ = [
    "IndexFileError",
    "index_path",
    "load",
    "new_revision",
    "open_model",
    "record_revision",
    "save",
    "snapshot",
    "stored_revision",
    "write_snapshot",
]

log = logging.getLogger(__name__)

FORMAT = 2
"""Bumped whenever the payload's layout changes: a file of another format is rebuilt.
Format 2 adds what opening would otherwise derive or rewrite: the index's bitsets, each class's
Z terms and child sums, and the score view the store holds (each class's written Z terms and
the memory state's factors), so that opening neither re-derives nor rewrites them."""
MAGIC = b"ENGRAM-MEMORY-INDEX\n"
_HEADER = struct.Struct(f"<{len(MAGIC)}sIQ32s")  # magic, format, payload length, SHA-256
SUFFIX = ".memory-index"

Weights = tuple[float, float, float, float]


class IndexFileError(ValueError):
    """The index file is missing, stale, truncated or corrupt (the message says which)."""


# Revision ------------------------------------------------------------------------------------


def new_revision() -> str:
    """A fresh revision token (random: a restored backup never matches a later file)."""
    return uuid.uuid4().hex


def stored_revision(store: Store) -> str | None:
    """The store's current scene-memory revision token, None before the first transaction."""
    for quad in store.quads(MEMORY_STATE_INDIVIDUAL, MEMORY_REVISION, None, MEMORY_REVISION_GRAPH):
        if isinstance(quad.object, Literal):
            return quad.object.value
    return None


def record_revision(tx: Transaction, old: str | None, new: str) -> None:
    """Replace the revision token ``old`` (what the memory last read or wrote) with ``new``."""
    node, graph = MEMORY_STATE_INDIVIDUAL, MEMORY_REVISION_GRAPH
    if old is None:
        tx.delete_matching(node, MEMORY_REVISION, None, graph=graph)
    else:
        tx.delete(node, MEMORY_REVISION, Literal(old), graph)
    tx.insert(node, MEMORY_REVISION, Literal(new), graph)


# Paths -------------------------------------------------------------------------------------


def index_path(store: Store) -> Path | None:
    """Where the index file of an on-disk store lives (``<store dir>.memory-index``), None for a
    store without a directory."""
    path: Path | None = getattr(store, "path", None)  # a remote store has none
    if path is None:
        return None
    return path.with_name(path.name + SUFFIX)


# Model <-> plain values ----------------------------------------------------------------------


def snapshot(model: MemoryModel, revision: str, weights: Weights) -> dict[str, Any]:
    """The model's stored facts as built-in values (what :func:`rebuild` needs), to be pickled
    outside the memory's lock."""
    keys: dict[Key, int] = {}

    def signature(sig: Signature) -> tuple[int, ...]:
        flat: list[int] = []
        for key, n in sig.items():
            number = keys.get(key)
            if number is None:
                number = keys[key] = len(keys)
            flat += (number, n)
        return tuple(flat)

    times: dict[dt.datetime, int] = {}
    time_texts: list[str] = []

    def stamp(value: dt.datetime) -> int:
        number = times.get(value)
        if number is None:
            number = times[value] = len(time_texts)
            time_texts.append(value.isoformat())
        return number

    derived = model.derived()  # first: it brings every Z up to date
    numbers = {cls: k for k, cls in enumerate(model.classes)}
    classes = [
        (
            r.iri.value,
            signature(r.signature),
            r.store_count,
            r.retrieve_count,
            r.score,
            stamp(r.created),
            stamp(r.last_accessed),
            r.weak_count,
            r.pinned,
            r.level,
        )
        for r in model.classes.values()
    ]
    parents = [tuple(numbers[p] for p in model.parents[cls]) for cls in model.classes]
    items = [
        (
            r.iri.value,
            numbers[r.cls],
            r.complexity,
            stamp(r.created),
            stamp(r.last_accessed),
            r.weak_count,
            r.pinned,
            r.level,
        )
        for r in model.items.values()
    ]
    trashed_classes = [
        (t.iri.value, signature(t.signature), stamp(t.forgotten_at))
        for t in model.trashed_classes.values()
    ]
    trashed_items = [
        (t.iri.value, t.cls.value, stamp(t.forgotten_at)) for t in model.trashed_items.values()
    ]
    stored = [(keys.setdefault(key, len(keys)), n) for key, n in model.stored_restrictions]
    index = None
    if derived is not None:
        at_least, by_complexity, scores = derived
        index = (
            [(keys.setdefault(key, len(keys)), levels) for key, levels in at_least.items()],
            by_complexity,
            scores,
        )
    return {
        "revision": revision,
        "weights": tuple(weights),
        "keys": [(p.value, t.value) for (p, t) in keys],
        "times": time_texts,
        "classes": classes,
        "parents": parents,
        "items": items,
        "trashed_classes": trashed_classes,
        "trashed_items": trashed_items,
        "stored_restrictions": stored,
        "derived": index,
        "view": (
            [r.written_z for r in model.classes.values()],
            model.written_factors,
        ),
        "state": (
            model.next_class,
            model.next_item,
            None if model.last_sleep_at is None else model.last_sleep_at.isoformat(),
            model.updates_since_sleep,
            model.sleep_passes,
            model.has_state,
        ),
    }


def rebuild(values: dict[str, Any], weights: Weights) -> MemoryModel:
    """The model a :func:`snapshot` describes (``KeyError``, ``TypeError`` or ``ValueError`` on a
    malformed one)."""
    named: dict[str, NamedNode] = {}

    def iri(text: str) -> NamedNode:
        node = named.get(text)
        if node is None:
            node = named[text] = NamedNode(text)
        return node

    keys = [(iri(p), iri(t)) for p, t in values["keys"]]
    times = [dt.datetime.fromisoformat(text) for text in values["times"]]

    def signature(flat: tuple[int, ...]) -> Signature:
        return Signature.trusted({keys[flat[k]]: flat[k + 1] for k in range(0, len(flat), 2)})

    records = [
        ClassRecord(
            iri=NamedNode(c[0]),
            signature=signature(c[1]),
            store_count=c[2],
            retrieve_count=c[3],
            score=c[4],
            created=times[c[5]],
            last_accessed=times[c[6]],
            weak_count=c[7],
            pinned=c[8],
            level=c[9],
        )
        for c in values["classes"]
    ]
    written, factors = values["view"]
    for record, z in zip(records, written, strict=True):
        record.written_z = None if z is None else (z[0], z[1], z[2])
    model = MemoryModel(weights=weights)
    edges = [
        (records[child].iri, records[parent].iri)
        for child, parents in enumerate(values["parents"])
        for parent in parents
    ]
    derived: Derived | None = None
    if values["derived"] is not None:
        at_least, by_complexity, scores = values["derived"]
        derived = (
            {keys[k]: levels for k, levels in at_least},
            by_complexity,
            [((z[0], z[1], z[2]), list(sums)) for z, sums in scores],
        )
    model.load(records, edges, derived=derived)
    model.written_factors = None if factors is None else tuple(factors)
    for i in values["items"]:
        model.add_item(
            ItemRecord(
                iri=NamedNode(i[0]),
                cls=records[i[1]].iri,
                complexity=i[2],
                created=times[i[3]],
                last_accessed=times[i[4]],
                weak_count=i[5],
                pinned=i[6],
                level=i[7],
            )
        )
    for cls, flat, at in values["trashed_classes"]:
        node = NamedNode(cls)
        model.trashed_classes[node] = TrashedClass(node, signature(flat), times[at])
    for item, cls, at in values["trashed_items"]:
        node = NamedNode(item)
        model.trashed_items[node] = TrashedItem(node, iri(cls), times[at])
    model.stored_restrictions = {(keys[k], n) for k, n in values["stored_restrictions"]}
    next_class, next_item, last_sleep, updates, passes, has_state = values["state"]
    model.next_class, model.next_item = next_class, next_item
    model.last_sleep_at = None if last_sleep is None else dt.datetime.fromisoformat(last_sleep)
    model.updates_since_sleep, model.sleep_passes, model.has_state = updates, passes, has_state
    return model


# The file ------------------------------------------------------------------------------------


def write_snapshot(path: Path, values: dict[str, Any]) -> None:
    """Write a :func:`snapshot` atomically: temporary file, fsync, rename, fsync of the folder."""
    payload = pickle.dumps(values, protocol=5)
    header = _HEADER.pack(MAGIC, FORMAT, len(payload), hashlib.sha256(payload).digest())
    for stale in path.parent.glob(path.name + ".*.tmp"):  # left by a process killed mid-write
        stale.unlink(missing_ok=True)
    temporary = path.with_name(f"{path.name}.{os.getpid()}.tmp")
    with open(temporary, "wb") as file:
        file.write(header)
        file.write(payload)
        file.flush()
        os.fsync(file.fileno())
    os.replace(temporary, path)
    folder = os.open(path.parent, os.O_RDONLY)
    try:
        os.fsync(folder)
    finally:
        os.close(folder)


def save(path: Path, model: MemoryModel, revision: str) -> None:
    """Save ``model``, the state of the store at ``revision``, to ``path`` atomically."""
    write_snapshot(path, snapshot(model, revision, model.weights))


class _BuiltinsOnly(pickle.Unpickler):
    """An unpickler that refuses every global: the payload can only hold built-in values."""

    def find_class(self, module: str, name: str) -> Any:
        raise pickle.UnpicklingError(f"global {module}.{name} refused in an index file")


def read(path: Path) -> dict[str, Any]:
    """The snapshot saved at ``path``. Raises :class:`IndexFileError` naming what is wrong."""
    try:
        data = path.read_bytes()
    except FileNotFoundError:
        raise IndexFileError(f"{path}: no index file") from None
    except OSError as error:
        raise IndexFileError(f"{path}: unreadable: {error}") from None
    if len(data) < _HEADER.size:
        raise IndexFileError(f"{path}: truncated: {len(data)} bytes, shorter than the header")
    magic, version, length, digest = _HEADER.unpack_from(data)
    if magic != MAGIC:
        raise IndexFileError(f"{path}: not an index file (magic {magic[:20]!r})")
    if version != FORMAT:
        raise IndexFileError(f"{path}: format {version}, expected {FORMAT}")
    payload = memoryview(data)[_HEADER.size :]
    if len(payload) != length:
        raise IndexFileError(f"{path}: truncated: {len(payload)} payload bytes, expected {length}")
    if hashlib.sha256(payload).digest() != digest:
        raise IndexFileError(f"{path}: corrupt: the payload does not match its SHA-256")
    try:
        values = _BuiltinsOnly(io.BytesIO(payload)).load()
    except (pickle.UnpicklingError, EOFError, ValueError, TypeError) as error:
        raise IndexFileError(f"{path}: corrupt payload: {error}") from None
    if not isinstance(values, dict):
        raise IndexFileError(f"{path}: corrupt payload: got {type(values).__name__}, not a dict")
    return values


def load(path: Path, revision: str | None, weights: Weights) -> MemoryModel | None:
    """The model saved at ``path`` if it mirrors the store at ``revision`` with ``weights``;
    None (the reason logged) if the file is missing, stale, truncated or corrupt."""
    try:
        values = read(path)
        if revision is None or values.get("revision") != revision:
            raise IndexFileError(
                f"{path}: stale: revision {values.get('revision')!r}, the store is at {revision!r}"
            )
        if tuple(values.get("weights", ())) != tuple(weights):
            raise IndexFileError(f"{path}: stale: written for weights {values.get('weights')}")
        return rebuild(values, weights)
    except IndexFileError as error:
        log.info("scene memory index not used: %s", error)
    except (KeyError, IndexError, TypeError, ValueError) as error:
        log.warning("scene memory index not used: %s: malformed payload: %r", path, error)
    return None


def open_model(
    store: Store, weights: Weights, rebuild_from_store: Callable[[], MemoryModel]
) -> tuple[MemoryModel, str | None, str]:
    """(model, the store's revision, "index file" or "store"): the model from the index file
    beside ``store`` when it is current, else ``rebuild_from_store()``."""
    revision = stored_revision(store)
    path = index_path(store)
    if path is not None and revision is not None:
        model = load(path, revision, weights)
        if model is not None:
            return model, revision, "index file"
    return rebuild_from_store(), revision, "store"
