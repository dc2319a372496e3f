"""The working state of one directive list: its net changes, its view of the store, its commit.

A list's writes are collected as net changes per graph (adding then removing a triple leaves
nothing), and committed together in one store transaction when every directive succeeded.
Directives that read see the committed store plus the list's own changes: as long as a
reference has no pending change, reads go straight to the store; once it has, triple-pattern
reads overlay the changes on the store, and SPARQL reads go to a copy of the reference's graphs
in a private in-memory store (a *workspace*, built at the first such read, following every later
change). Other clients never see a list's changes before its commit.

Reasoning never copies a reference: the list tells the reasoner what it wrote since it last
reasoned (:mod:`api.armor.reasoning`), gets the inferred graph's delta back, and commits that
delta with its own changes. Memory directives (:mod:`api.armor.memory`) queue scene memory
operations as values (:mod:`reasoners.operations`); at the commit the session hands them and the
list's other writes, as a :class:`kg.transaction.Transaction`, to
:meth:`reasoners.memory.SceneMemory.commit`, which runs the operations in order and writes
everything in one transaction, so a list with two scenes, or a reference write and a scene,
commits all of it or none. The results come back as values that the directives turn into their
responses.
"""

import logging
from collections.abc import Callable, Iterable
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

from pyoxigraph import BlankNode, Literal, NamedNode, Quad, QuerySolutions

import sparql
from api.armor import reasoning
from api.armor.errors import MEMORY_ERROR, SparqlError
from api.armor.references import Reference, Registry
from api.protocol import ArmorDirectiveRes
from kg import QueryError, Store
from kg.literals import from_store
from kg.transaction import Transaction
from reasoners.errors import MemoryReasonerError, OperationFailedError
from reasoners.operations import Operation, OperationResult
from reasoners.owl_rl import Prepared

if TYPE_CHECKING:  # api.armor.memory imports this module (through api.armor.context)
    from api.armor.memory import MemoryDirectives

__all__ = ["ChangeSet", "MemoryWorkFailed", "Row", "Session"]

log = logging.getLogger(__name__)

Row = dict[str, NamedNode | Literal]


class MemoryWorkFailed(Exception):
    """A memory directive's work failed at the commit; its response says why, nothing stayed."""


Answer = Callable[[OperationResult, ArmorDirectiveRes], None]
"""Fills in a directive's response from its operation's result."""


@dataclass(frozen=True)
class _Queued:
    """A memory directive's operation, waiting for the commit, and where its answer goes."""

    operation: Operation
    answer: Answer | None
    response: ArmorDirectiveRes


@dataclass
class ChangeSet:
    """Net changes to one graph: ``cleared`` first, then ``removed``, then ``added``.

    The added quads are indexed by subject and by object, so that a directive reading a pattern
    costs the same at the 20,000th directive of a list as at the first.
    """

    cleared: bool = False
    added: dict[Quad, None] = field(default_factory=dict)
    removed: set[Quad] = field(default_factory=set)
    _by_subject: dict[Any, dict[Quad, None]] = field(default_factory=dict, repr=False)
    _by_object: dict[Any, dict[Quad, None]] = field(default_factory=dict, repr=False)

    def __post_init__(self) -> None:
        for quad in self.added:
            self._index(quad)

    def _index(self, quad: Quad) -> None:
        self._by_subject.setdefault(quad.subject, {})[quad] = None
        self._by_object.setdefault(quad.object, {})[quad] = None

    def _unindex(self, quad: Quad) -> None:
        for index, key in ((self._by_subject, quad.subject), (self._by_object, quad.object)):
            bucket = index.get(key)
            if bucket is not None:
                bucket.pop(quad, None)
                if not bucket:
                    del index[key]

    def insert(self, quad: Quad) -> None:
        self.removed.discard(quad)
        self.added[quad] = None
        self._index(quad)

    def delete(self, quad: Quad) -> None:
        if quad in self.added:
            del self.added[quad]
            self._unindex(quad)
        if not self.cleared:  # the store may hold it too
            self.removed.add(quad)

    def clear(self) -> None:
        self.cleared, self.added, self.removed = True, {}, set()
        self._by_subject, self._by_object = {}, {}

    def added_matching(
        self,
        subject: NamedNode | BlankNode | None,
        predicate: NamedNode | None,
        obj: NamedNode | BlankNode | Literal | None,
    ) -> list[Quad]:
        """The added quads that match a pattern (``None`` matches anything), in insertion order."""
        if subject is not None:
            candidates: Iterable[Quad] = self._by_subject.get(subject, {})
        elif obj is not None:
            candidates = self._by_object.get(obj, {})
        else:
            candidates = self.added
        return [
            q
            for q in candidates
            if (subject is None or q.subject == subject)
            and (predicate is None or q.predicate == predicate)
            and (obj is None or q.object == obj)
        ]

    @property
    def is_empty(self) -> bool:
        return not (self.cleared or self.added or self.removed)


@dataclass
class _Unreasoned:
    """A list's writes to a reference that its reasoner has not seen yet."""

    added: list[Quad] = field(default_factory=list)
    removed: list[Quad] = field(default_factory=list)
    cleared: bool = False
    inferred_written: bool = False
    """A directive wrote the inferred graph itself (RENAME): the reasoner must recompute."""

    def note(self, reference: Reference, quad: Quad, *, added: bool) -> None:
        if quad.graph_name != reference.asserted:
            self.inferred_written = True
        elif added:
            self.added.append(quad)
        else:
            self.removed.append(quad)


class Session:
    """One directive list, run against ``store`` and ``registry`` while holding their locks.

    ``memory`` is the memory directives' adapter (:class:`api.armor.memory.MemoryDirectives`);
    without it, a directive that needs the scene memory answers ARMOR's memory error (212, see
    :meth:`api.armor.context.Context.scene_memory`). ``scenes`` holds the clients' open scenes
    between lists.
    """

    def __init__(
        self,
        store: Store,
        registry: Registry,
        *,
        memory: "MemoryDirectives | None" = None,
        scenes: dict[tuple[str, str], Any] | None = None,
    ) -> None:
        self.store = store
        self.registry = registry
        self.memory = memory
        self._scenes_base = scenes if scenes is not None else {}
        self.scenes: dict[tuple[str, str], Any] = {}
        self.queued: list[_Queued] = []
        """The memory directives' operations, run at the commit in this order."""
        self.references: dict[str, Reference | None] = {}
        self.changes: dict[NamedNode, ChangeSet] = {}
        self.workspaces: dict[str, Store] = {}
        self.needs_reasoning: set[str] = set()
        self.unreasoned: dict[str, _Unreasoned] = {}
        """Per reference: the list's writes its reasoner has not seen yet."""
        self.prepared: dict[str, Prepared] = {}
        """Per reference: the reasoner's last delta for this list (confirmed after the commit)."""

    # References ---------------------------------------------------------------------------------

    def reference(self, name: str) -> Reference | None:
        """The reference as this list sees it (its own changes included)."""
        if name in self.references:
            return self.references[name]
        return self.registry.get(name)

    def require(self, name: str) -> Reference:
        reference = self.reference(name)
        if reference is None:
            return self.registry.require(name)  # raises UnknownReferenceError
        return reference

    def update(self, reference: Reference) -> None:
        self.references[reference.name] = reference

    def drop(self, name: str) -> None:
        reference = self.require(name)
        for graph in reference.graphs:
            self._changes(graph).clear()
        self.workspaces.pop(name, None)
        self.needs_reasoning.discard(name)
        prepared = self.prepared.pop(name, None)
        if prepared is not None:
            prepared.discard()
        self.unreasoned[name] = _Unreasoned(cleared=True)
        self.references[name] = None

    def names(self) -> list[str]:
        names = set(self.registry.names())
        for name, reference in self.references.items():
            if reference is None:
                names.discard(name)
            else:
                names.add(name)
        return sorted(names)

    # Open scenes (memory directives) -------------------------------------------------------------

    def scene(self, key: tuple[str, str]) -> Any:
        """The open scene of (client, reference) as this list sees it, or None."""
        if key in self.scenes:
            return self.scenes[key]
        return self._scenes_base.get(key)

    def set_scene(self, key: tuple[str, str], draft: Any) -> None:
        self.scenes[key] = draft

    def queue(
        self, operation: Operation, answer: Answer | None, response: ArmorDirectiveRes
    ) -> None:
        """Run ``operation`` at the commit, in the list's transaction; then ``answer`` fills in
        ``response`` from its result."""
        self.queued.append(_Queued(operation, answer, response))

    # Writes -------------------------------------------------------------------------------------

    def _changes(self, graph: NamedNode) -> ChangeSet:
        return self.changes.setdefault(graph, ChangeSet())

    def write(
        self,
        reference: Reference,
        *,
        insert: Iterable[Quad] = (),
        delete: Iterable[Quad] = (),
    ) -> None:
        """Record deletions, then insertions, for ``reference``'s graphs."""
        insert, delete = list(insert), list(delete)
        if not (insert or delete):
            return
        todo = self.unreasoned.setdefault(reference.name, _Unreasoned())
        for quad in delete:
            self._require_own_graph(reference, quad)
            self._changes(quad.graph_name).delete(quad)  # type: ignore[arg-type]
            todo.note(reference, quad, added=False)
        for quad in insert:
            self._require_own_graph(reference, quad)
            self._changes(quad.graph_name).insert(quad)  # type: ignore[arg-type]
            todo.note(reference, quad, added=True)
        workspace = self.workspaces.get(reference.name)
        if workspace is not None and (insert or delete):
            with workspace.transaction() as tx:
                tx.deletes.extend(delete)
                tx.inserts.extend(insert)

    @staticmethod
    def _require_own_graph(reference: Reference, quad: Quad) -> None:
        if quad.graph_name not in (reference.asserted, reference.inferred):
            raise ValueError(f"{quad} is not in a graph of reference {reference.name!r}")

    def _pending(self, reference: Reference) -> bool:
        if not self.changes:
            return False
        return any(
            not self.changes[graph].is_empty for graph in reference.graphs if graph in self.changes
        )

    # Reads --------------------------------------------------------------------------------------

    def quads(
        self,
        reference: Reference,
        subject: NamedNode | None = None,
        predicate: NamedNode | None = None,
        obj: NamedNode | Literal | None = None,
        *,
        graph: NamedNode | None = None,
    ) -> list[Quad]:
        """Quads of ``reference`` (one of its graphs, or both) as this list sees them."""
        self._catch_up(reference)
        graphs = [graph] if graph is not None else reference.graphs
        workspace = self.workspaces.get(reference.name)
        found: list[Quad] = []
        for g in graphs:
            if workspace is not None:
                found.extend(workspace.quads(subject, predicate, obj, g))
                continue
            changes = self.changes.get(g)
            if changes is None:  # the common case, kept short: a directive reads many patterns
                found.extend(self.store.quads(subject, predicate, obj, g))
                continue
            if not changes.cleared:
                found.extend(
                    q
                    for q in self.store.quads(subject, predicate, obj, g)
                    if q not in changes.removed
                )
            found.extend(changes.added_matching(subject, predicate, obj))
        return found

    def select(self, reference: Reference, name: str, **bindings: NamedNode | Literal) -> list[Row]:
        """Rows of the stored query ``sparql/<name>.rq`` over ``reference``'s graphs."""
        result = self.query(reference, sparql.load(name), bindings)
        if not isinstance(result, QuerySolutions):
            raise TypeError(f"query {name!r} is not a SELECT query")
        names = [variable.value for variable in result.variables]
        return [
            {n: from_store(t) for n in names if isinstance(t := row[n], NamedNode | Literal)}
            for row in result
        ]

    def query(
        self,
        reference: Reference,
        text: str,
        bindings: dict[str, NamedNode | Literal] | None = None,
    ) -> object:
        """Run query text over ``reference``'s asserted and inferred graphs."""
        store = self.view_store(reference)
        try:
            return store.query_graphs(text, graphs=reference.graphs, bindings=bindings)
        except QueryError as error:
            raise SparqlError(f"args: the SPARQL query was refused: {error}") from None

    def view_store(self, reference: Reference) -> Store:
        """The store to read ``reference`` from: the real one, or this list's workspace."""
        self._catch_up(reference)
        if reference.name in self.workspaces:
            return self.workspaces[reference.name]
        if not self._pending(reference):
            return self.store
        return self._workspace(reference)

    def _workspace(self, reference: Reference) -> Store:
        workspace = Store()
        with workspace.transaction() as tx:
            for graph in reference.graphs:
                changes = self.changes.get(graph, ChangeSet())
                if not changes.cleared:
                    tx.inserts.extend(
                        q for q in self.store.quads(graph=graph) if q not in changes.removed
                    )
                tx.inserts.extend(changes.added)
        self.workspaces[reference.name] = workspace
        log.debug("workspace for %s: %d quads", reference.name, len(workspace))
        return workspace

    # Reasoning ----------------------------------------------------------------------------------

    def reason_later(self, reference: Reference) -> None:
        """Bring the inferences up to date before the next read, or before the commit."""
        self.needs_reasoning.add(reference.name)

    def _catch_up(self, reference: Reference) -> None:
        if reference.name in self.needs_reasoning:
            self.needs_reasoning.discard(reference.name)
            self.reason_now(reference)

    def reason_now(self, reference: Reference) -> None:
        """Materialise ``reference``'s inferences as this list sees its assertions.

        With nothing of this list pending on the reference, the reasoner brings the committed
        inferred graph up to date on the store itself (derived from committed assertions only, it
        stays right whatever the rest of the list does). Otherwise the reasoner computes the
        inferred graph's delta for the list's writes since its previous reasoning, and the delta
        joins the list's changes: it commits with them, or goes with them.
        """
        name = reference.name
        todo = self.unreasoned.pop(name, None)
        after = self.prepared.get(name)
        if after is None and todo is None and not self._pending(reference):
            consistent = reasoning.reason_committed(self.store, reference)
        else:
            todo = todo or _Unreasoned()
            asserted = self.changes.get(reference.asserted, ChangeSet())
            prepared = reasoning.prepare(
                self.store,
                reference,
                added=todo.added,
                removed=todo.removed,
                pending_added=list(asserted.added),
                pending_removed=list(asserted.removed),
                cleared=asserted.cleared,
                after=after,
                recompute=todo.inferred_written,
            )
            self.prepared[name] = prepared
            self._apply_inferred(reference, prepared)
            consistent = prepared.consistent
        current = self.reference(name)
        if current is not None:
            self.update(current.with_changes(consistent=consistent))

    def _apply_inferred(self, reference: Reference, prepared: Prepared) -> None:
        """Put a delta of the inferred graph into this list's changes (and its workspace)."""
        if prepared.replaces:  # relative to the committed graph: it replaces the earlier delta
            self.changes[reference.inferred] = ChangeSet(
                added=dict.fromkeys(prepared.added), removed=set(prepared.removed)
            )
            self.workspaces.pop(reference.name, None)  # rebuilt if a later read needs it
            return
        changes = self._changes(reference.inferred)
        for quad in prepared.removed:
            changes.delete(quad)
        for quad in prepared.added:
            changes.insert(quad)
        workspace = self.workspaces.get(reference.name)
        if workspace is not None and (prepared.added or prepared.removed):
            with workspace.transaction() as tx:
                tx.deletes.extend(prepared.removed)
                tx.inserts.extend(prepared.added)

    def _settle_reasoner(self) -> None:
        """After the commit: keep the reasoner's state in step with what was committed."""
        if not (self.prepared or self.unreasoned):
            return
        for name in sorted(set(self.prepared) | set(self.unreasoned)):
            reference = self.references.get(name) or Reference(name=name, prefix="")
            prepared = self.prepared.pop(name, None)
            todo = self.unreasoned.pop(name, None)
            try:
                if prepared is not None:
                    prepared.confirm(self.store)
                if todo is None:
                    continue
                if todo.cleared or todo.inferred_written:
                    reasoning.forget_state(self.store, reference)
                elif todo.added or todo.removed:  # the next REASON derives from the list
                    reasoning.record_committed(
                        self.store, reference, added=todo.added, removed=todo.removed
                    )
            except Exception:  # never leave a state that may not match the store
                log.exception("the reasoner's state of reference %s is dropped", name)
                reasoning.forget_state(self.store, reference)

    def discard(self) -> None:
        """The list does not commit: drop the reasoner's tentative states of its references."""
        for prepared in self.prepared.values():
            prepared.discard()
        self.prepared = {}
        self.unreasoned = {}

    # Commit -------------------------------------------------------------------------------------

    def commit(self) -> None:
        """Reason where needed, write every change of the list in one transaction, publish."""
        pending, self.needs_reasoning = sorted(self.needs_reasoning), set()
        for name in pending:
            reference = self.reference(name)
            if reference is None:
                continue
            try:
                self.reason_now(reference)
            except Exception:  # the assertions still commit; the next REASON recomputes
                log.exception("reasoning over the list's writes failed for reference %s", name)
        if self.queued:
            self._commit_with_memory()
        elif self.changes or self.references:  # a list that only read takes no store lock
            with self.store.transaction() as tx:
                self._add_writes(tx)
        self._settle_reasoner()
        self.registry.publish(self.references)
        for key, draft in self.scenes.items():
            if draft is None:
                self._scenes_base.pop(key, None)
            else:
                self._scenes_base[key] = draft
        self.changes, self.workspaces = {}, {}

    def _commit_with_memory(self) -> None:
        """Hand the queued operations and the list's other writes to the scene memory, which
        commits them in one transaction; then answer each operation's directive.

        Raises :class:`MemoryWorkFailed` (after writing the error into the failing directive's
        response) when an operation fails: nothing of the list stays, and the memory's model is
        as before the list.
        """
        if self.memory is None:  # the directives that queue operations check for it first
            raise RuntimeError("scene memory operations queued in a session without a memory")
        queued, self.queued = self.queued, []
        writes = Transaction()
        self._add_writes(writes)
        try:
            results = self.memory.memory.commit(
                [q.operation for q in queued], writes, sleep_if_due=True
            )
        except OperationFailedError as failure:
            response, error = queued[failure.index].response, failure.error
            response.success, response.exit_code = False, MEMORY_ERROR
            if isinstance(error, MemoryReasonerError | ValueError):  # refused: the message says why
                response.error_description = f"{error} (nothing of the list stayed)"
            else:
                log.error("memory operation failed", exc_info=error)
                response.error_description = (
                    f"memory pipeline failed, nothing of the list stayed: {error!r}"
                )
            raise MemoryWorkFailed(response.error_description) from None
        for item, result in zip(queued, results, strict=True):
            if item.answer is not None:
                item.answer(result, item.response)

    def _add_writes(self, tx: Transaction) -> None:
        """Add every change of the list (its graphs, its references' settings) to ``tx``."""
        for graph, changes in self.changes.items():
            if changes.cleared:
                tx.clear_graph(graph)
            tx.deletes.extend(changes.removed)
            tx.inserts.extend(changes.added)
        for name, reference in self.references.items():
            old = self.registry.get(name)
            if old is not None and (reference is None or _settings_changed(old, reference)):
                tx.deletes.extend(old.settings_quads())
            if reference is not None and (old is None or _settings_changed(old, reference)):
                tx.inserts.extend(reference.settings_quads())


def _settings_changed(old: Reference, new: Reference) -> bool:
    return old.settings_quads() != new.settings_quads()
