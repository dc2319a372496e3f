"""What a command handler receives (:class:`Context`) and returns (:class:`Outcome`)."""

from collections.abc import Callable
from dataclasses import dataclass, field

from pyoxigraph import Literal, NamedNode, Quad

from api.armor.errors import InvalidArgumentsError, MemoryDirectiveError
from api.armor.files import ANYWHERE, FileAccess
from api.armor.names import ValueStyle, resolve
from api.armor.references import Reference
from api.armor.session import Session
from api.protocol import ArmorDirectiveReq, ArmorDirectiveRes, QueryItem
from kg.sandbox import QueryRunner
from reasoners.memory import SceneMemory
from reasoners.operations import Operation, OperationResult

__all__ = ["Context", "Outcome"]


@dataclass
class Outcome:
    """A handled directive: ``success`` and ``exit_code`` as ARMOR sets them, and any results."""

    queried_objects: list[str] = field(default_factory=list)
    sparql_queried_objects: list[QueryItem] = field(default_factory=list)
    success: bool = True
    exit_code: int = 0
    error_description: str = ""
    timeout: bool = False
    operation: Operation | None = None
    """A scene memory operation that the list's commit runs, in its transaction."""
    answer: Callable[[OperationResult, ArmorDirectiveRes], None] | None = None
    """Fills in the response from the operation's result, once the list has committed."""


@dataclass
class Context:
    """One directive being executed inside a :class:`Session`."""

    session: Session
    request: ArmorDirectiveReq
    key: str
    signature: str
    style: ValueStyle = "armor"
    applying: bool = False
    """True while APPLY replays a buffered directive: it writes instead of queueing again."""
    sandbox: QueryRunner | None = None
    """Where QUERY SPARQL runs a client's text; None runs it in this process (no server)."""
    files: FileAccess = ANYWHERE
    """Where LOAD FILE, SAVE and LOG FILE may go and what LOAD WEB may fetch."""

    @property
    def client(self) -> str:
        return self.request.client_name

    @property
    def args(self) -> list[str]:
        return self.request.args

    def reference(self) -> Reference:
        """The directive's reference; raises UnknownReferenceError if it is not loaded."""
        return self.session.require(self.request.reference_name)

    def scene_memory(self) -> SceneMemory:
        """The scene memory behind the memory directives; raises :class:`MemoryDirectiveError`
        (212) naming the directive when the session has none."""
        directives = self.session.memory
        if directives is None:
            raise MemoryDirectiveError(
                f"{self.key.replace('_', ' ').strip()}: this session has no scene memory; "
                "memory directives run only in an engine built over one"
            )
        return directives.memory

    def arg(self, index: int, what: str) -> str:
        """``args[index]``; raises InvalidArgumentsError naming what the command expects."""
        if index >= len(self.args):
            raise InvalidArgumentsError(
                f"args[{index}] ({what}): missing; {self.key.replace('_', ' ').strip()} expects "
                f"args {self.signature}, got {len(self.args)} arg(s)"
            )
        return self.args[index]

    def name(self, index: int, what: str) -> NamedNode:
        """``args[index]`` as an entity IRI of the directive's reference."""
        return resolve(self.arg(index, what), self.reference().prefix, field=f"args[{index}]")

    def buffered(self) -> bool:
        """Queue the directive if the reference buffers manipulations; True if it was queued.

        Call after the arguments are checked, before writing, so that a queued directive is
        known to be well-formed.
        """
        reference = self.reference()
        if self.applying or not reference.buffered_manipulation:
            return False
        self.session.update(reference.with_changes(buffer=(*reference.buffer, self.request)))
        return True

    def quad(self, subject: NamedNode, predicate: NamedNode, obj: NamedNode | Literal) -> Quad:
        """A quad in the reference's asserted graph."""
        return Quad(subject, predicate, obj, self.reference().asserted)

    def write(self, *, insert: list[Quad] | None = None, delete: list[Quad] | None = None) -> None:
        """Write to the reference, and keep an unbuffered reasoner up to date."""
        reference = self.reference()
        self.session.write(reference, insert=insert or (), delete=delete or ())
        if not reference.buffered_reasoner:
            self.session.reason_later(reference)
