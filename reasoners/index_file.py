"""The scene memory's in-memory model saved beside the store, so that opening reads one file.

Rebuilding the model from triples (:func:`reasoners.persist.load_model`) reads every learned
class, edge and experienced scene through SPARQL: seconds at 10,000 classes. The index file holds
the same facts as plain values (IRIs as strings, signatures as key numbers, times as ISO text),
laid out as columns (signatures and edges as packed arrays) with what the model derives from
them (the index's bitsets, each class's Z terms), so that opening reads it with bulk calls and
re-derives nothing (under two seconds at 100,000 classes), and falls back to the triples
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
import itertools
import logging
import os
import pickle
import struct
import uuid
from collections import Counter
from collections.abc import Callable, Iterable
from pathlib import Path
from typing import Any, cast

import numpy as np
from numpy.typing import NDArray
from pyoxigraph import Literal, NamedNode

from kg.errors import EngramError
from kg.store import Store
from kg.transaction import Transaction
from ontologies.vocab import MEMORY_REVISION, MEMORY_REVISION_GRAPH, MEMORY_STATE_INDIVIDUAL
from reasoners.class_graph import Restriction
from reasoners.collector import collector_paused
from reasoners.model import MemoryModel
from reasoners.records import ClassRecord, ItemRecord, TrashedClass, TrashedItem
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

FORMAT = 3
"""Bumped whenever the payload's layout changes: a file of another format is rebuilt.
Format 2 added what opening would otherwise derive or rewrite: the index's bitsets, each class's
Z terms and child sums, and the score view the store holds (each class's written Z terms and
the memory state's factors). Format 3 holds the classes as columns, their signatures and edges
(both directions) as packed arrays, so that opening does no Python work per signature key or
per edge."""
MAGIC = b"ENGRAM-MEMORY-INDEX\n"
_HEADER = struct.Struct(f"<{len(MAGIC)}sIQ32s")  # magic, format, payload length, SHA-256
SUFFIX = ".memory-index"

Weights = tuple[float, float, float, float]


class IndexFileError(EngramError, ValueError):
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


def _u32(values: Iterable[int]) -> bytes:
    """Non-negative integers as packed little-endian 32-bit words (:func:`_ints` reads them)."""
    return np.fromiter(values, dtype="<u4").tobytes()


def _ints(packed: bytes) -> list[int]:
    """The integers :func:`_u32` packed: ints by construction (``ValueError`` on a ragged
    length), so that a whole column is read, and checked, in one call."""
    return cast(list[int], np.frombuffer(packed, dtype="<u4").tolist())


def _ends(lengths: list[int], total: int, what: str) -> list[int]:
    """Where each class's run of a flat column ends, checked against the column's length."""
    ends = list(itertools.accumulate(lengths))
    if (ends[-1] if ends else 0) != total:
        raise ValueError(f"{what}: the lengths add up to {ends[-1:]}, the column holds {total}")
    return ends


def _runs(flat: list[Any], ends: list[int]) -> list[list[Any]]:
    """``flat`` cut at ``ends``: one run per class."""
    return [flat[start:end] for start, end in zip([0, *ends], ends, strict=False)]


def snapshot(model: MemoryModel, revision: str, weights: Weights) -> dict[str, Any]:
    """The model's stored facts as built-in values (what :func:`rebuild` needs), to be pickled
    outside the memory's lock.

    Classes are columns (one list or packed array per field) and signatures and edges flat
    packed arrays with per-class lengths, so that reading them back is a few bulk calls rather
    than Python work per class (format 3).
    """
    # a few hundred thousand lists, all kept until pickled
    with collector_paused(age_survivors=True):
        return _snapshot(model, revision, weights)


def _snapshot(model: MemoryModel, revision: str, weights: Weights) -> dict[str, Any]:
    keys: dict[Key, int] = {}

    def key_number(key: Key) -> int:
        number = keys.get(key)
        if number is None:
            number = keys[key] = len(keys)
        return number

    def signature(sig: Signature) -> tuple[int, ...]:
        flat: list[int] = []
        for key, n in sig.items():
            flat += (key_number(key), n)
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
    records = list(model.graph.classes.values())
    numbers = {cls: k for k, cls in enumerate(model.graph.classes)}
    signatures = [r.signature for r in records]
    parents = [list(map(numbers.__getitem__, model.graph.parents[r.iri])) for r in records]
    flat_keys = list(itertools.chain.from_iterable(signatures))
    for key in dict.fromkeys(flat_keys):  # the few distinct keys numbered first
        key_number(key)
    classes = (
        [r.iri.value for r in records],
        _u32(map(len, signatures)),
        _u32(map(keys.__getitem__, flat_keys)),
        _u32(itertools.chain.from_iterable(sig.values() for sig in signatures)),
        [r.store_count for r in records],
        [r.retrieve_count for r in records],
        [r.score for r in records],
        [stamp(r.created) for r in records],
        [stamp(r.last_accessed) for r in records],
        [r.weak_count for r in records],
        [r.pinned for r in records],
        [r.level for r in records],
        [r.written_z for r in records],
    )
    edges = _edge_columns(parents)
    items = list(model.items.records.values())
    item_columns = (
        [r.iri.value for r in items],
        [numbers[r.cls] for r in items],
        [r.complexity for r in items],
        [stamp(r.created) for r in items],
        [stamp(r.last_accessed) for r in items],
        [r.weak_count for r in items],
        [r.pinned for r in items],
        [r.level for r in items],
    )
    trashed_classes = [
        (t.iri.value, signature(t.signature), stamp(t.forgotten_at))
        for t in model.trash.classes.values()
    ]
    trashed_items = [
        (t.iri.value, t.cls.value, stamp(t.forgotten_at)) for t in model.trash.items.values()
    ]
    stored = [(key_number(key), n) for key, n in model.graph.stored_restrictions]
    index = None
    if derived is not None:
        at_least, by_complexity, scores = derived
        index = (
            [(key_number(key), levels) for key, levels in at_least.items()],
            by_complexity,
            [[z[x] for z, _ in scores] for x in range(3)],
            [[sums[x] for _, sums in scores] for x in range(3)],
        )
    return {
        "revision": revision,
        "weights": tuple(weights),
        "keys": [(p.value, t.value) for (p, t) in keys],
        "times": time_texts,
        "classes": classes,
        "edges": edges,
        "items": item_columns,
        "trashed_classes": trashed_classes,
        "trashed_items": trashed_items,
        "stored_restrictions": stored,
        "derived": index,
        "factors": model.scores.written_factors,
        "state": (
            model.state.next_class,
            model.state.next_item,
            None if model.state.last_sleep_at is None else model.state.last_sleep_at.isoformat(),
            model.state.updates_since_sleep,
            model.state.sleep_passes,
            model.state.has_state,
        ),
    }


def _edge_columns(parents: list[list[int]]) -> tuple[bytes, bytes, bytes, bytes]:
    """The packed (parent lengths, parents, child lengths, children) of the classes whose
    parents are ``parents[k]``: the children are the parents inverted, in numpy (the model keeps
    ``children`` the inverse of ``parents``)."""
    lengths = np.fromiter(map(len, parents), dtype=np.intp, count=len(parents))
    above = np.fromiter(itertools.chain.from_iterable(parents), dtype=np.intp)
    below = np.repeat(np.arange(len(parents)), lengths)
    by_parent = np.argsort(above, kind="stable")
    return (
        lengths.astype("<u4").tobytes(),
        above.astype("<u4").tobytes(),
        np.bincount(above, minlength=len(parents)).astype("<u4").tobytes(),
        below[by_parent].astype("<u4").tobytes(),
    )


def rebuild(values: dict[str, Any], weights: Weights) -> MemoryModel:
    """The model a :func:`snapshot` describes (``KeyError``, ``IndexError``, ``TypeError`` or
    ``ValueError`` on a malformed one). Every column is read with bulk calls (``map`` over the
    column, packed arrays decoded by numpy); what remains per class is building its objects."""
    named: dict[str, NamedNode] = {}

    def iri(text: str) -> NamedNode:
        node = named.get(text)
        if node is None:
            node = named[text] = NamedNode(text)
        return node

    keys = [(iri(p), iri(t)) for p, t in values["keys"]]
    times = [dt.datetime.fromisoformat(text) for text in values["times"]]
    stamps = times.__getitem__

    def signature(flat: tuple[int, ...]) -> Signature:
        return Signature.trusted({keys[flat[k]]: flat[k + 1] for k in range(0, len(flat), 2)})

    (iris, lengths, key_column, count_column, stores, retrieves, scores, created, accessed,
     weak, pinned, levels, written) = values["classes"]  # fmt: skip
    nodes = list(map(NamedNode, iris))
    size = len(nodes)
    columns = (stores, retrieves, scores, created, accessed, weak, pinned, levels, written)
    if any(len(column) != size for column in columns):
        raise ValueError(f"classes: columns of {[len(c) for c in columns]}, not {size}")
    restrictions = _Restrictions(keys, key_column, count_column)
    signatures = _signatures(keys, restrictions, lengths, key_column, count_column, size)
    up, down = _edges(values["edges"], size)
    derived = values["derived"]
    model = MemoryModel(weights=weights)
    if derived is None:  # a class was removed: the index and Z are derived again
        records = list(
            map(ClassRecord, nodes, signatures, stores, retrieves, scores,
                map(stamps, created), map(stamps, accessed), weak, pinned, levels)
        )  # fmt: skip
        for record, z in zip(records, written, strict=True):
            record.written_z = None if z is None else (z[0], z[1], z[2])
        model.load(records, [(nodes[c], nodes[p]) for c, run in enumerate(up) for p in run])
    else:
        at_least, by_complexity, z_columns, sum_columns = derived
        zs = list(zip(*z_columns, strict=True))
        sums = list(map(list, zip(*sum_columns, strict=True)))
        if len(zs) != size or len(sums) != size:
            raise ValueError(f"scores: {len(zs)} Z and {len(sums)} sums for {size} classes")
        records = list(
            map(ClassRecord, nodes, signatures, stores, retrieves, scores,
                map(stamps, created), map(stamps, accessed), weak, pinned, levels,
                zs, sums, itertools.repeat(None), map(len, down), itertools.repeat(0),
                written)
        )  # fmt: skip
        record_at, node_at = records.__getitem__, nodes.__getitem__
        for record, run in zip(records, up, strict=True):
            record.up = list(map(record_at, run))
        model.restore(
            records,
            [set(map(node_at, run)) for run in up],
            [set(map(node_at, run)) for run in down],
            {keys[k]: levels for k, levels in at_least},
            by_complexity,
            restrictions.counter(),
        )
    model.scores.written_factors = None if values["factors"] is None else tuple(values["factors"])
    item_iris, classes_of, complexities, item_created, item_accessed, *rest = values["items"]
    model.items.add_all(
        map(ItemRecord, map(NamedNode, item_iris), map(nodes.__getitem__, classes_of),
            complexities, map(stamps, item_created), map(stamps, item_accessed), *rest)
    )  # fmt: skip
    for cls, flat, at in values["trashed_classes"]:
        node = NamedNode(cls)
        model.trash.classes[node] = TrashedClass(node, signature(flat), times[at])
    for item, cls, at in values["trashed_items"]:
        node = NamedNode(item)
        model.trash.items[node] = TrashedItem(node, iri(cls), times[at])
    model.graph.stored_restrictions = {(keys[k], n) for k, n in values["stored_restrictions"]}
    next_class, next_item, last_sleep, updates, passes, has_state = values["state"]
    model.state.next_class, model.state.next_item = next_class, next_item
    model.state.last_sleep_at = (
        None if last_sleep is None else dt.datetime.fromisoformat(last_sleep)
    )
    model.state.updates_since_sleep, model.state.sleep_passes, model.state.has_state = (
        updates,
        passes,
        has_state,
    )
    return model


class _Restrictions:
    """The restrictions (key, count) of every signature, from the packed columns: each distinct
    one hashed and counted once, in numpy, rather than millions of tuples hashed one by one."""

    def __init__(self, keys: list[Key], key_column: bytes, count_column: bytes) -> None:
        key_numbers = np.frombuffer(key_column, dtype="<u4")
        counts = np.frombuffer(count_column, dtype="<u4")
        if len(key_numbers) != len(counts):
            raise ValueError(f"signatures: {len(key_numbers)} keys, {len(counts)} counts")
        if len(counts) and (counts.min() < 1 or key_numbers.max() >= len(keys)):
            raise ValueError("signatures: a count below 1 or a key number out of range")
        width = int(counts.max(initial=0)) + 1
        codes = key_numbers.astype(np.int64) * width + counts  # one number per restriction
        if len(keys) * width <= _TABLE:  # counted in a dense table
            table = np.bincount(codes)
            distinct = np.flatnonzero(table)
            uses = table[distinct]
            rank = np.zeros(len(table), dtype=np.int32)
            rank[distinct] = np.arange(len(distinct))
            inverse = rank[codes]
        else:  # a huge count: sorted instead
            distinct, inverse, uses = np.unique(codes, return_inverse=True, return_counts=True)
        self.distinct: list[Restriction] = [
            (keys[code // width], code % width) for code in distinct.tolist()
        ]
        self.uses: list[int] = uses.tolist()
        hashes = np.array([hash(restriction) for restriction in self.distinct], dtype=np.int64)
        self.item_hashes: NDArray[np.int64] = hashes[inverse]
        """``hash((key, count))`` of every entry of the columns."""

    def counter(self) -> Counter[Restriction]:
        """How many signatures use each restriction (:attr:`ClassGraph.restrictions`)."""
        return Counter(dict(zip(self.distinct, self.uses, strict=True)))


_TABLE = 1 << 24
"""The most (key, count) cells a dense table of restrictions may have."""


def _signatures(
    keys: list[Key],
    restrictions: _Restrictions,
    lengths: bytes,
    key_column: bytes,
    count_column: bytes,
    size: int,
) -> list[Signature]:
    """The classes' signatures from the packed columns (their counts and keys checked at once by
    :class:`_Restrictions`), built by :meth:`Signature.unchecked_runs`."""
    counts = _ints(count_column)
    sig_keys = list(map(keys.__getitem__, _ints(key_column)))
    ends = _ends(_ints(lengths), len(counts), "signatures")
    if len(ends) != size:
        raise ValueError(f"signatures: {len(ends)} for {size} classes")
    return Signature.unchecked_runs(sig_keys, counts, ends, restrictions.item_hashes)


def _edges(
    columns: tuple[bytes, bytes, bytes, bytes], size: int
) -> tuple[list[list[int]], list[list[int]]]:
    """(each class's parents, each class's children) as class numbers, from the packed columns."""
    parent_lengths, parent_column, child_lengths, child_column = columns
    parents, children = _ints(parent_column), _ints(child_column)
    up = _runs(parents, _ends(_ints(parent_lengths), len(parents), "parents"))
    down = _runs(children, _ends(_ints(child_lengths), len(children), "children"))
    if len(up) != size or len(down) != size:
        raise ValueError(f"edges: {len(up)} parent and {len(down)} child lists for {size} classes")
    return up, down


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
    write_snapshot(path, snapshot(model, revision, model.scores.weights))


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
        with collector_paused(age_survivors=True):
            values = read(path)
            if revision is None or values.get("revision") != revision:
                raise IndexFileError(
                    f"{path}: stale: revision {values.get('revision')!r}, "
                    f"the store is at {revision!r}"
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
