"""ARMOR references: their settings, mount and buffer, and the registry that keeps them.

A reference is two named graphs (``reference_graph(name)`` for what was asserted and
``reference_graph(name, inferred=True)`` for what REASON materialised) plus settings. The
settings are stored as triples in the ``armor`` registry graph, written in the same transaction
as the graphs, so references survive a restart. The mount entry and the manipulation buffer live
in memory only, as in ARMOR: a restart unmounts everyone and drops unapplied changes.

>>> ref = Reference(name="tutorial", prefix="http://ex.org/t")
>>> ref.asserted.value
'https://w3id.org/engram/graph/ref/tutorial'
>>> ref.is_available("anyone")
True
"""

import re
import threading
from collections.abc import Iterable, Iterator
from contextlib import contextmanager
from dataclasses import dataclass, replace
from functools import lru_cache
from urllib.parse import quote

from pyoxigraph import Literal, NamedNode, Quad

from api.armor.errors import InvalidArgumentsError, UnknownReferenceError
from api.protocol import ArmorDirectiveReq
from kg import Store
from ontologies.vocab import (
    ARMOR_BUFFERED_MANIPULATION,
    ARMOR_BUFFERED_REASONER,
    ARMOR_NAME,
    ARMOR_NS,
    ARMOR_PREFIX,
    ARMOR_REASONER,
    ARMOR_REFERENCE,
    ARMOR_REGISTRY,
    ARMOR_SOURCE,
    ARMOR_SOURCE_FORMAT,
    RDF_TYPE,
    reference_graph,
)

__all__ = ["NOBODY", "Reference", "Registry", "check_reference_name"]

NOBODY = "none"
"""The mount entry of a reference nobody is mounted on (ARMOR's literal string)."""
_NAME = re.compile(r"^[A-Za-z0-9_.~-]+$")


def check_reference_name(name: str) -> str:
    """Return ``name`` if it can name a reference (it becomes part of a graph IRI).

    Raises :class:`InvalidArgumentsError` otherwise.
    """
    if not _NAME.match(name):
        raise InvalidArgumentsError(
            f"reference_name: got {name!r}, expected letters, digits, '_', '-', '.' or '~'"
        )
    return name


@lru_cache(maxsize=1024)
def _graphs(name: str) -> tuple[NamedNode, NamedNode]:
    """The asserted and inferred graphs of reference ``name``.

    A directive reads them about a dozen times, often from a fresh copy of its reference:
    building the IRIs each time cost several microseconds of a simple directive's ~150.
    """
    return reference_graph(name), reference_graph(name, inferred=True)


@dataclass(frozen=True)
class Reference:
    """One loaded ontology and its settings. Immutable: a directive list changes a copy."""

    name: str
    prefix: str
    buffered_manipulation: bool = False
    reasoner: str = "PELLET"
    buffered_reasoner: bool = False
    source: str = ""
    source_format: str = ""
    mounted: str = NOBODY
    buffer: tuple[ArmorDirectiveReq, ...] = ()
    consistent: bool = True

    @property
    def asserted(self) -> NamedNode:
        return _graphs(self.name)[0]

    @property
    def inferred(self) -> NamedNode:
        return _graphs(self.name)[1]

    @property
    def graphs(self) -> list[NamedNode]:
        return list(_graphs(self.name))

    @property
    def node(self) -> NamedNode:
        return NamedNode(ARMOR_NS + "reference/" + quote(self.name, safe=""))

    def is_available(self, client: str) -> bool:
        """True if ``client`` may manipulate: nobody, or that client, is mounted."""
        return self.mounted in (NOBODY, client)

    def with_changes(self, **changes: object) -> "Reference":
        return replace(self, **changes)  # type: ignore[arg-type]

    def settings_quads(self) -> list[Quad]:
        """The registry triples describing this reference's persistent settings."""
        node, graph = self.node, ARMOR_REGISTRY
        quads = [
            Quad(node, RDF_TYPE, ARMOR_REFERENCE, graph),
            Quad(node, ARMOR_NAME, Literal(self.name), graph),
            Quad(node, ARMOR_PREFIX, Literal(self.prefix), graph),
            Quad(node, ARMOR_BUFFERED_MANIPULATION, Literal(self.buffered_manipulation), graph),
            Quad(node, ARMOR_REASONER, Literal(self.reasoner), graph),
            Quad(node, ARMOR_BUFFERED_REASONER, Literal(self.buffered_reasoner), graph),
            Quad(node, ARMOR_SOURCE, Literal(self.source), graph),
            Quad(node, ARMOR_SOURCE_FORMAT, Literal(self.source_format), graph),
        ]
        return quads


class Registry:
    """The references by name, with one write lock per name.

    Reads (``get``, ``names``) take no lock: a directive list publishes its changed references
    only after its transaction committed, so readers see committed states.
    """

    def __init__(self, store: Store) -> None:
        self.store = store
        self._references: dict[str, Reference] = {}
        self._locks: dict[str, threading.Lock] = {}
        self._locks_guard = threading.Lock()
        self._load()

    def _load(self) -> None:
        settings: dict[str, dict[str, list[Literal | NamedNode]]] = {}
        for quad in self.store.quads(graph=ARMOR_REGISTRY):
            if isinstance(quad.object, Literal | NamedNode) and isinstance(quad.subject, NamedNode):
                fields = settings.setdefault(quad.subject.value, {})
                fields.setdefault(quad.predicate.value, []).append(quad.object)
        for fields in settings.values():

            def one(term: NamedNode, fields: dict[str, list[Literal | NamedNode]] = fields) -> str:
                values = fields.get(term.value, [])
                return values[0].value if values else ""

            name = one(ARMOR_NAME)
            if not name:
                continue
            self._references[name] = Reference(
                name=name,
                prefix=one(ARMOR_PREFIX),
                buffered_manipulation=one(ARMOR_BUFFERED_MANIPULATION) == "true",
                reasoner=one(ARMOR_REASONER) or "PELLET",
                buffered_reasoner=one(ARMOR_BUFFERED_REASONER) == "true",
                source=one(ARMOR_SOURCE),
                source_format=one(ARMOR_SOURCE_FORMAT),
            )

    def get(self, name: str) -> Reference | None:
        return self._references.get(name)

    def require(self, name: str) -> Reference:
        """The reference called ``name``; raises :class:`UnknownReferenceError` if there is none."""
        reference = self._references.get(name)
        if reference is None:
            raise UnknownReferenceError(
                f"reference_name: no reference {name!r} is loaded; "
                "load it first with LOAD FILE or LOAD WEB"
            )
        return reference

    def names(self) -> list[str]:
        return sorted(self._references)

    def publish(self, changed: dict[str, Reference | None]) -> None:
        """Make committed changes visible: a reference, or ``None`` for a dropped one."""
        for name, reference in changed.items():
            if reference is None:
                self._references.pop(name, None)
            else:
                self._references[name] = reference

    @contextmanager
    def locked(self, names: Iterable[str], *, wait: bool = True) -> Iterator[bool]:
        """Hold the write locks of ``names``, taken in sorted order so that lists never deadlock.

        Yields True once they are held; with ``wait=False``, yields False at once (holding none)
        if one of them is taken.
        """
        with self._locks_guard:
            locks = [self._locks.setdefault(name, threading.Lock()) for name in sorted(set(names))]
        for taken, lock in enumerate(locks):
            try:
                acquired = lock.acquire(blocking=wait)
            except BaseException:
                acquired = False
                for held in locks[:taken]:
                    held.release()
                raise
            if not acquired:
                for held in locks[:taken]:
                    held.release()
                yield False
                return
        try:
            yield True
        finally:
            for lock in reversed(locks):
                lock.release()
