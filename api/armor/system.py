"""LOAD, SAVE, MOUNT, UNMOUNT, DROP, GET and LOG: the commands the mount never gates."""

import logging
import threading
from collections.abc import Callable
from pathlib import Path
from urllib.parse import urlparse

import httpx
from pyoxigraph import NamedNode, Quad

from api.armor.context import Context, Outcome
from api.armor.errors import CANNOT_MOUNT, InvalidArgumentsError, ResourceError
from api.armor.files import FileAccess
from api.armor.names import is_true
from api.armor.rdfio import file_kind, parse_ontology, write_ontology
from api.armor.references import NOBODY, Reference, check_reference_name
from kg.skolem import is_skolem
from ontologies.vocab import OWL_ONTOLOGY, RDF_TYPE

__all__ = ["HANDLERS", "REASONERS"]

log = logging.getLogger(__name__)

REASONERS = ("PELLET", "HERMIT", "FACT", "SNOROCKET", "OWL2RL")
"""The reasoner names ARMOR accepts; all run Engram's OWL 2 RL + SWRL materialiser."""
_WEB_TIMEOUT_S = 30.0


def _reasoner(name: str) -> str:
    if not name:
        return "PELLET"
    if name.upper() not in REASONERS:
        raise InvalidArgumentsError(
            f"args[3]: got reasoner {name!r}, expected one of {', '.join(REASONERS)} or ''"
        )
    return name.upper()


def _read_file(path: Path, shown: str) -> bytes:
    try:
        return path.read_bytes()
    except OSError as error:
        raise ResourceError(f"args[0]: cannot read {shown!r}: {error.strerror or error}") from None


_MAX_REDIRECTS = 5


def _read_web(url: str, files: FileAccess) -> bytes:
    """The document at ``url``, following redirects only to URLs ``files`` allows."""
    try:
        with httpx.Client(timeout=_WEB_TIMEOUT_S, follow_redirects=False) as client:
            for _ in range(_MAX_REDIRECTS + 1):
                response = client.get(files.url(url))
                if not response.is_redirect:
                    response.raise_for_status()
                    return response.content
                url = str(response.next_request.url) if response.next_request else ""
    except httpx.HTTPError as error:
        raise ResourceError(f"args[0]: cannot fetch {url!r}: {error}") from None
    raise ResourceError(f"args[0]: more than {_MAX_REDIRECTS} redirects from {url!r}")


def _load(ctx: Context, *, web: bool, mounted: bool) -> Outcome:
    name = check_reference_name(ctx.request.reference_name)
    source = ctx.arg(0, "file path" if not web else "URL")
    prefix = ctx.arg(1, "ontology IRI").rstrip("#")
    args = ctx.args
    buffered_manipulation = is_true(args[2]) if len(args) > 2 else False
    reasoner = _reasoner(args[3] if len(args) > 3 else "")
    buffered_reasoner = is_true(args[4]) if len(args) > 4 else False
    try:
        NamedNode(prefix + "#x")
    except ValueError:
        raise InvalidArgumentsError(f"args[1]: got {args[1]!r}, expected an IRI") from None
    session = ctx.session
    existing = session.reference(name)
    if existing is not None:
        log.warning("LOAD: reference %s exists; not reloaded, flags re-applied", name)
        session.update(existing.with_changes(buffered_manipulation=buffered_manipulation))
    else:
        reference = Reference(
            name=name,
            prefix=prefix,
            buffered_manipulation=buffered_manipulation,
            reasoner=reasoner,
            buffered_reasoner=buffered_reasoner,
            source=source,
        )
        if source:
            if web:
                content, base = _read_web(source, ctx.files), source
            else:
                path = ctx.files.path(source)
                content, base = _read_file(path, source), path.resolve().as_uri()
            triples, kind = parse_ontology(content, name=source, base_iri=base)
            reference = reference.with_changes(source_format=kind)
        else:  # Engram's extension: an empty path starts an empty ontology named by the IRI
            triples, reference = [], reference.with_changes(source_format="rdfxml")
        session.update(reference)
        quads = [Quad(t.subject, t.predicate, t.object, reference.asserted) for t in triples]
        if not source:
            quads.append(Quad(NamedNode(prefix), RDF_TYPE, OWL_ONTOLOGY, reference.asserted))
        session.write(reference, insert=quads)
        if source or not buffered_reasoner:
            # ARMOR's reasoner, buffered or not, starts on the ontology as loaded: its
            # inferences are there before the first REASON; later changes wait for REASON.
            session.reason_later(reference)
        log.info("LOAD %s: %d triples from %r", name, len(quads), source)
    if mounted:
        return _mount(ctx, loaded=True)
    return Outcome()


def load_file(ctx: Context) -> Outcome:
    return _load(ctx, web=False, mounted=False)


def load_file_mounted(ctx: Context) -> Outcome:
    return _load(ctx, web=False, mounted=True)


def load_web(ctx: Context) -> Outcome:
    return _load(ctx, web=True, mounted=False)


def load_web_mounted(ctx: Context) -> Outcome:
    return _load(ctx, web=True, mounted=True)


def _mount(ctx: Context, *, loaded: bool = False) -> Outcome:
    name, client = ctx.request.reference_name, ctx.client
    reference = ctx.session.reference(name)
    if reference is None:
        return Outcome(
            success=False,
            exit_code=CANNOT_MOUNT,
            error_description=(
                f"{client} cannot be mounted on {name}. The reference does not exist."
            ),
        )
    if reference.mounted == client:
        log.warning("MOUNT: %s is already mounted on %s", client, name)
        return Outcome()
    if reference.mounted == NOBODY:
        ctx.session.update(reference.with_changes(mounted=client))
        return Outcome()
    if loaded:
        description = (
            f"Reference loaded from file but {client} cannot be mounted on reference {name}. "
            "Another client is already mounted on it."
        )
    else:
        description = (
            f"{client} cannot be mounted on {name}. Another client is already mounted on it."
        )
    return Outcome(success=False, exit_code=CANNOT_MOUNT, error_description=description)


def mount(ctx: Context) -> Outcome:
    return _mount(ctx)


def unmount(ctx: Context) -> Outcome:
    reference = ctx.reference()
    if reference.mounted == ctx.client:
        ctx.session.update(reference.with_changes(mounted=NOBODY))
    else:
        log.warning("UNMOUNT: %s is not mounted on %s", ctx.client, reference.name)
    return Outcome()


def drop(ctx: Context) -> Outcome:
    ctx.session.drop(ctx.reference().name)
    return Outcome()


def _save(ctx: Context, *, inference: bool) -> Outcome:
    reference = ctx.reference()
    target = ctx.args[0] if ctx.args else ""
    if not target:
        if not reference.source or urlparse(reference.source).scheme in ("http", "https"):
            raise InvalidArgumentsError(
                f"args[0]: empty, but reference {reference.name!r} was not loaded from a file "
                "to overwrite; give a path"
            )
        target = reference.source
        kind = reference.source_format
    else:
        kind = reference.source_format if reference.source else file_kind(target)
    quads = ctx.session.quads(reference, graph=reference.asserted)
    if inference:
        rows = ctx.session.select(reference, "armor_inferred_abox", inferred=reference.inferred)
        quads += [
            Quad(row["s"], row["p"], row["o"], reference.asserted)  # type: ignore[arg-type]
            for row in rows
            # ARMOR exports what the OWL API's reasoner answers: named classes, individuals and
            # literals, never a class expression (a skolem IRI here)
            if isinstance(row.get("s"), NamedNode)
            and isinstance(row.get("p"), NamedNode)
            and not (is_skolem(row["s"]) or is_skolem(row.get("o")))
        ]
    write_ontology(list(dict.fromkeys(quads)), ctx.files.path(target), kind)
    log.info("SAVE %s to %s (%d triples)", reference.name, target, len(quads))
    return Outcome()


def save(ctx: Context) -> Outcome:
    return _save(ctx, inference=False)


def save_inference(ctx: Context) -> Outcome:
    return _save(ctx, inference=True)


def get_all_refs(ctx: Context) -> Outcome:
    return Outcome(queried_objects=ctx.session.names())


def get_ref_client(ctx: Context) -> Outcome:
    name = ctx.arg(0, "reference name")
    reference = ctx.session.require(name)
    return Outcome(queried_objects=[reference.mounted])


_log_lock = threading.Lock()
_log_handlers: dict[str, logging.Handler] = {}
_ARMOR_LOGGER = logging.getLogger("api.armor")


def _switch_log(kind: str, on: bool, make: Callable[[], logging.Handler]) -> None:
    with _log_lock:
        old = _log_handlers.pop(kind, None)
        if old is not None:
            _ARMOR_LOGGER.removeHandler(old)
            old.close()
        if on:
            handler = make()
            handler.setFormatter(
                logging.Formatter("%(asctime)s %(levelname)s %(name)s %(message)s")
            )
            _log_handlers[kind] = handler
            _ARMOR_LOGGER.addHandler(handler)
            if _ARMOR_LOGGER.getEffectiveLevel() > logging.INFO:
                _ARMOR_LOGGER.setLevel(logging.INFO)


def log_file_on(ctx: Context) -> Outcome:
    given = ctx.arg(0, "log file path")
    path = ctx.files.path(given)
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        with open(path, "a", encoding="utf-8"):
            pass
    except OSError as error:
        reason = error.strerror or type(error).__name__
        raise ResourceError(f"args[0]: cannot write the log file {given!r}: {reason}") from None
    _switch_log("file", True, lambda: logging.FileHandler(path, encoding="utf-8"))
    return Outcome()


def log_file_off(ctx: Context) -> Outcome:
    _switch_log("file", False, logging.NullHandler)
    return Outcome()


def log_screen_on(ctx: Context) -> Outcome:
    _switch_log("screen", True, logging.StreamHandler)
    return Outcome()


def log_screen_off(ctx: Context) -> Outcome:
    _switch_log("screen", False, logging.NullHandler)
    return Outcome()


HANDLERS: dict[str, Callable[[Context], Outcome]] = {
    "LOAD_FILE_": load_file,
    "LOAD_FILE_MOUNTED": load_file_mounted,
    "LOAD_WEB_": load_web,
    "LOAD_WEB_MOUNTED": load_web_mounted,
    "SAVE__": save,
    "SAVE_INFERENCE_": save_inference,
    "MOUNT__": mount,
    "UNMOUNT__": unmount,
    "DROP__": drop,
    "GET_ALL_REFS": get_all_refs,
    "GET_REF_CLIENT": get_ref_client,
    "LOG_FILE_ON": log_file_on,
    "LOG_FILE_OFF": log_file_off,
    "LOG_SCREEN_ON": log_screen_on,
    "LOG_SCREEN_OFF": log_screen_off,
}
