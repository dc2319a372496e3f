"""Dispatch: a directive's key to its handler, mount checks, and one transaction per list."""

import logging
import threading
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import NamedTuple

from api.armor import manipulation, queries, system
from api.armor.context import Context, Outcome
from api.armor.errors import (
    BUSY,
    INTERNAL_ERROR,
    NO_COMMAND,
    NO_REFERENCE,
    UNKNOWN_COMMAND,
    DirectiveError,
    DirectiveListTooLongError,
)
from api.armor.files import ANYWHERE, FileAccess
from api.armor.memory import MEMORY_COMMANDS, SCENE_ADDS, MemoryDirectives
from api.armor.names import ValueStyle
from api.armor.references import Registry
from api.armor.session import MemoryWorkFailed, Session
from api.protocol import ArmorDirectiveListRes, ArmorDirectiveReq, ArmorDirectiveRes
from kg import Store
from kg.sandbox import QueryRunner
from reasoners.memory import SceneMemory

__all__ = ["COMMANDS", "ArmorEngine", "Command", "directive_key"]

log = logging.getLogger(__name__)

Handler = Callable[[Context], Outcome]


@dataclass(frozen=True)
class Command:
    """One row of the command table."""

    handler: Handler
    signature: str
    kind: str  # "system", "query" or "manipulation" (gated by the mount)


def apply(ctx: Context) -> Outcome:
    """Run the directives queued by buffered manipulation, in order."""
    reference = ctx.reference()
    queued = reference.buffer
    ctx.session.update(reference.with_changes(buffer=()))
    for request in queued:
        key = directive_key(request)
        replay = Context(
            ctx.session,
            request,
            key,
            COMMANDS[key].signature,
            applying=True,
            sandbox=ctx.sandbox,
            files=ctx.files,
        )
        outcome = COMMANDS[key].handler(replay)
        if not outcome.success:
            raise DirectiveError(
                f"APPLY: the queued {key} failed: {outcome.error_description}", outcome.exit_code
            )
    return Outcome()


def reason(ctx: Context) -> Outcome:
    """APPLY, then bring the inferred graph up to date (before the next read or the commit)."""
    apply(ctx)
    ctx.session.reason_later(ctx.reference())
    return Outcome()


_SIGNATURES = {
    "LOAD_FILE_": "[path, iri, buffered_manipulation, reasoner, buffered_reasoner]",
    "LOAD_WEB_": "[url, iri, buffered_manipulation, reasoner, buffered_reasoner]",
    "SAVE__": "[path]",
    "GET_REF_CLIENT": "[reference]",
    "LOG_FILE_ON": "[path]",
    "ADD_IND_": "[individual]",
    "ADD_CLASS_": "[class]",
    "ADD_IND_CLASS": "[individual, class]",
    "ADD_CLASS_CLASS": "[subclass, superclass]",
    "ADD_DATAPROP_IND": "[property, individual, type, value]",
    "ADD_OBJECTPROP_IND": "[property, individual, value individual]",
    "ADD_CARDINALITY_MIN": "[class, property, n, value class]",
    "DISJOINT_IND_": "[individual, individual, ...]",
    "DISJOINT_CLASS_": "[class, class, ...]",
    "DISJOINT_IND_CLASS": "[class]",
    "DISJOINT_CLASS_CLASS": "[class]",
    "MAKE_EQUIVALENT_CLASS": "[class]",
    "REMOVE_IND_": "[individual]",
    "REMOVE_CLASS_": "[class]",
    "REMOVE_IND_CLASS": "[individual, class]",
    "REMOVE_CLASS_CLASS": "[subclass, superclass]",
    "REMOVE_DATAPROP_IND": "[property, individual, type, value]",
    "REMOVE_OBJECTPROP_IND": "[property, individual, value individual]",
    "REPLACE_DATAPROP_IND": "[property, individual, type, new value, old value]",
    "REPLACE_OBJECTPROP_IND": "[property, individual, new value, old value]",
    "RENAME_IND_": "[old name, new name]",
    "QUERY_IND_": "[individual]",
    "QUERY_IND_CLASS": "[class]",
    "QUERY_DATAPROP_IND": "[property, individual]",
    "QUERY_OBJECTPROP_IND": "[property, individual]",
    "QUERY_CLASS_IND": "[individual, bottom]",
    "QUERY_CLASS_CLASS": "[class]",
    "QUERY_CLASS_RESTRICTIONS": "[class]",
    "QUERY_IND_DATAPROP": "[individual]",
    "QUERY_IND_OBJECTPROP": "[individual]",
    "QUERY_SPARQL_": "[query] or [prefix, select, where] (+ timeout_ms)",
}


def _table() -> dict[str, Command]:
    table: dict[str, Command] = {}
    for handlers, kind in (
        (system.HANDLERS, "system"),
        (queries.HANDLERS, "query"),
        (manipulation.HANDLERS, "manipulation"),
        ({"APPLY__": apply, "REASON__": reason}, "manipulation"),
        ({key: handler for key, (handler, _) in MEMORY_COMMANDS.items()}, "memory"),
    ):
        for key, handler in handlers.items():
            signature = (
                _SIGNATURES.get(key)
                or MEMORY_COMMANDS.get(key, ("", ""))[1]
                or _SIGNATURES.get(key.rsplit("_", 1)[0] + "_", "[]")
            )
            table[key] = Command(handler, signature, kind)
    return table


COMMANDS = _table()
"""ARMOR's command map (``ARMORCommandExecutive.initializeCommands``) plus Engram's keys."""
_NEEDS_NO_REFERENCE = {
    "GET_ALL_REFS",
    "LOG_FILE_ON",
    "LOG_FILE_OFF",
    "LOG_SCREEN_ON",
    "LOG_SCREEN_OFF",
}


_SIMPLE_WRITES = ("ADD_", "REMOVE_", "REPLACE_", "DISJOINT_IND_")
_NO_COMMAND = Command(lambda ctx: Outcome(), "", "")
_SLOW_QUERIES = {"QUERY_SPARQL_", "QUERY_SPARQL_FORMATTED"}
_BEFORE_DISPATCH = {NO_REFERENCE, NO_COMMAND, UNKNOWN_COMMAND}
"""Codes ARMOR answers before reaching a reference, leaving ``is_consistent`` false."""


def directive_key(request: ArmorDirectiveReq) -> str:
    """ARMOR's key: ``upper(command_primary_secondary)``, nothing trimmed.

    >>> directive_key(ArmorDirectiveReq(command="add", primary_command_spec="ind"))
    'ADD_IND_'
    """
    return "_".join(
        (request.command, request.primary_command_spec, request.secondary_command_spec)
    ).upper()


class ArmorEngine:
    """Runs directives against the references kept in ``store``."""

    def __init__(
        self,
        store: Store,
        *,
        scene_memory: SceneMemory | None = None,
        sandbox: QueryRunner | None = None,
        max_list_length: int | None = None,
        files: FileAccess = ANYWHERE,
    ) -> None:
        self.store = store
        self.files = files
        """Where the file commands may go (:mod:`api.armor.files`); anywhere by default."""
        self.max_list_length = max_list_length
        """Most directives one list may hold; None for no limit."""
        self.sandbox = sandbox
        """Runs QUERY SPARQL's text in worker processes; None runs it in this process."""
        self.registry = Registry(store)
        self.commands = dict(COMMANDS)
        self.memory = MemoryDirectives(store, scene_memory)
        self._running = 0  # lists being executed, in any thread
        self._counting = threading.Lock()

    def is_quick_read(self, request: ArmorDirectiveReq) -> bool:
        """True for a directive that reads a few triples and takes no lock: any QUERY but
        QUERY SPARQL (whose caller-written query may run long). The HTTP route runs these on
        its event loop instead of a worker thread.

        >>> engine = ArmorEngine(Store())
        >>> engine.is_quick_read(ArmorDirectiveReq(command="QUERY", primary_command_spec="IND"))
        True
        >>> engine.is_quick_read(ArmorDirectiveReq(command="QUERY", primary_command_spec="SPARQL"))
        False
        """
        key = directive_key(request)
        command = self.commands.get(key)
        return command is not None and command.kind == "query" and key not in _SLOW_QUERIES

    def register(self, key: str, command: Command) -> None:
        """Add a directive to the table (memory directives, plugins)."""
        self.commands[key] = command

    def execute(
        self, request: ArmorDirectiveReq, *, style: ValueStyle = "armor"
    ) -> ArmorDirectiveRes:
        """One directive (a list of one)."""
        ran = self._execute_list([request], style, wait=True)
        assert ran is not None
        return ran.responses[0]

    def execute_list(
        self, requests: Sequence[ArmorDirectiveReq], *, style: ValueStyle = "armor"
    ) -> ArmorDirectiveListRes:
        """Every directive in order, then one commit if none failed (otherwise nothing stays).

        Raises :class:`DirectiveListTooLongError` for a list longer than ``max_list_length``.
        """
        if self.max_list_length is not None and len(requests) > self.max_list_length:
            raise DirectiveListTooLongError(len(requests), self.max_list_length)
        ran = self._execute_list(requests, style, wait=True)
        assert ran is not None
        return ArmorDirectiveListRes(
            success=ran.success, is_consistent=ran.consistent, armor_responses=ran.responses
        )

    def execute_now(
        self, request: ArmorDirectiveReq, *, style: ValueStyle = "armor"
    ) -> ArmorDirectiveRes | None:
        """One directive, if it cannot be made to wait; None (nothing done) otherwise.

        For callers that must not block (the HTTP route's event loop): a quick read
        (:meth:`is_quick_read`) always runs; a simple write (ADD, REMOVE, REPLACE, DISJOINT IND)
        runs if its reference reasons only on REASON (so that the commit involves no reasoning),
        no other list is running, and the reference's lock is free.
        """
        if self.is_quick_read(request):
            return self.execute(request, style=style)
        key = directive_key(request)
        reference = self.registry.get(request.reference_name)
        if (
            self._running
            or not key.startswith(_SIMPLE_WRITES)
            or self.commands.get(key, _NO_COMMAND).kind != "manipulation"
            or reference is None
            or not (reference.buffered_reasoner or reference.buffered_manipulation)
        ):
            return None
        ran = self._execute_list([request], style, wait=False)
        return None if ran is None else ran.responses[0]

    def _execute_list(
        self, requests: Sequence[ArmorDirectiveReq], style: ValueStyle, *, wait: bool
    ) -> "_Ran | None":
        with self._counting:
            self._running += 1
        try:
            return self._run_list(requests, style, wait=wait)
        finally:
            with self._counting:
                self._running -= 1

    def _run_list(
        self, requests: Sequence[ArmorDirectiveReq], style: ValueStyle, *, wait: bool
    ) -> "_Ran | None":
        keys = [directive_key(r) for r in requests]
        writers = {
            r.reference_name
            for r, key in zip(requests, keys, strict=True)
            if r.reference_name
            and (command := self.commands.get(key)) is not None
            and command.kind != "query"
            and not key.startswith("QUERY_")
            and key not in _NEEDS_NO_REFERENCE
        }
        with self.registry.locked(writers, wait=wait) as locked:
            if not locked:
                return None
            session = Session(
                self.store,
                self.registry,
                memory=self.memory,
                scenes=self.memory.scenes,
            )
            committed = False
            try:
                responses = [self._run(session, request, style) for request in requests]
                failed = any(not r.success and r.exit_code != 0 for r in responses)
                if not failed:
                    try:
                        session.commit()
                        committed = True
                    except MemoryWorkFailed:  # its directive's response says why
                        failed = True
                    except Exception as error:
                        log.exception("a directive list could not be committed")
                        failed = True
                        for response in responses:
                            if response.success:
                                response.success = False
                                response.exit_code = INTERNAL_ERROR
                                response.error_description = (
                                    f"the list's transaction could not be written, nothing "
                                    f"changed: {error}"
                                )
            finally:
                if not committed:
                    session.discard()  # the reasoner's tentative states for the list's writes
        consistent = True
        for request, response in zip(requests, responses, strict=True):
            reference = self.registry.get(request.reference_name)
            if reference is not None and response.exit_code not in _BEFORE_DISPATCH:
                response.is_consistent = reference.consistent
                consistent = consistent and reference.consistent
        return _Ran(responses, success=not failed, consistent=consistent and bool(requests))

    def _run(
        self, session: Session, request: ArmorDirectiveReq, style: ValueStyle
    ) -> ArmorDirectiveRes:
        if not request.reference_name:
            return _error(NO_REFERENCE, "Invalid request. No reference name specified.")
        if not request.command:
            return _error(NO_COMMAND, "Invalid request. No command specified.")
        key = directive_key(request)
        command = self.commands.get(key)
        if command is None:
            return _error(
                UNKNOWN_COMMAND,
                "Malformed command. No Command/Specs combination match found. "
                "Please check your service requests and retry.",
            )
        ctx = Context(
            session,
            request,
            key,
            command.signature,
            style=style,
            sandbox=self.sandbox,
            files=self.files,
        )
        try:
            draft = session.scene((request.client_name, request.reference_name))
            if draft is not None and key in SCENE_ADDS:
                return _response(SCENE_ADDS[key](ctx, draft), session)
            if command.kind == "manipulation":
                reference = ctx.reference()
                if not reference.is_available(ctx.client):
                    return _error(
                        BUSY,
                        f"{ctx.client} cannot connect to {reference.name}. "
                        "Another client is already mounted on it.",
                    )
            elif command.kind == "query":
                ctx.reference()
            outcome = command.handler(ctx)
        except DirectiveError as error:
            response = _error(error.exit_code, error.description)
            response.timeout = error.timeout
            return response
        except Exception as error:
            log.exception("directive %s failed", key)
            return _error(INTERNAL_ERROR, f"{key}: internal error, nothing changed: {error!r}")
        return _response(outcome, session)


class _Ran(NamedTuple):
    """A list that ran: its responses, and the list response's two flags."""

    responses: list[ArmorDirectiveRes]
    success: bool
    consistent: bool


def _response(outcome: Outcome, session: Session) -> ArmorDirectiveRes:
    response = ArmorDirectiveRes(
        success=outcome.success,
        timeout=outcome.timeout,
        exit_code=outcome.exit_code,
        error_description=outcome.error_description,
        queried_objects=outcome.queried_objects,
        sparql_queried_objects=outcome.sparql_queried_objects,
    )
    if outcome.operation is not None:
        session.queue(outcome.operation, outcome.answer, response)
    return response


def _error(code: int, description: str) -> ArmorDirectiveRes:
    return ArmorDirectiveRes(success=False, exit_code=code, error_description=description)
