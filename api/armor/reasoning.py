"""REASON's engine, :mod:`reasoners.owl_rl` (OWL 2 RL + DL-safe SWRL), fed with what lists wrote.

ARMOR's reasoner names (PELLET, HERMIT, FACT, SNOROCKET) are accepted as aliases of it.

The directive layer knows every change to a reference's asserted graph (it makes them), so the
reasoner never re-reads a whole graph to find them:

- a list that reasons over its own pending writes gets the inferred graph's delta from
  :func:`prepare` (the list's writes since its previous reasoning, against the reasoner's kept
  state), puts it into its own changes, and commits it with them; then :func:`confirm`, or on
  failure :func:`discard`, which makes the next REASON recompute;
- a list that commits writes without reasoning (a buffered reasoner) hands them to
  :func:`record`, retractions included, so that the next REASON derives their consequences
  only (for a retraction: re-derives the region of the closure it touches);
- a REASON with nothing pending in its list runs on the store (:func:`reason_committed`).
"""

import logging
from collections.abc import Sequence
from typing import cast

from pyoxigraph import Literal, NamedNode, Quad

from api.armor.errors import ReasonerFailure
from api.armor.references import Reference
from kg import Store
from reasoners.owl_rl import (
    AssertedChanges,
    Clash,
    PendingChanges,
    Prepared,
    ReasonerError,
    forget,
    materialise,
    record,
)
from reasoners.owl_rl import prepare as prepare_delta

__all__ = ["forget_state", "prepare", "reason_committed", "record_committed"]

log = logging.getLogger(__name__)

Triple = tuple[NamedNode, NamedNode, NamedNode | Literal]


def _triples(quads: Sequence[Quad]) -> list[Triple]:
    """The quads' triples (the directive layer writes no blank nodes: they are skolem IRIs)."""
    return cast("list[Triple]", [(q.subject, q.predicate, q.object) for q in quads])


def _log_clashes(reference: Reference, clashes: Sequence[Clash]) -> None:
    for clash in clashes:
        log.info("reference %s is inconsistent: %s", reference.name, clash)


def reason_committed(store: Store, reference: Reference) -> bool:
    """Bring the committed inferred graph up to date with the committed assertions; consistent?"""
    try:
        report = materialise(
            store,
            asserted=reference.asserted,
            inferred=reference.inferred,
            reasoner=reference.reasoner,
            changes=AssertedChanges(),  # everything since the last REASON was record()ed
        )
    except ReasonerError as error:
        raise ReasonerFailure(f"REASON on {reference.name}: {error}") from None
    _log_clashes(reference, report.clashes)
    return report.consistent


def prepare(
    store: Store,
    reference: Reference,
    *,
    added: Sequence[Quad],
    removed: Sequence[Quad],
    pending_added: Sequence[Quad],
    pending_removed: Sequence[Quad],
    cleared: bool,
    after: Prepared | None,
    recompute: bool,
) -> Prepared:
    """The inferred graph's delta for a list's uncommitted writes (see the module docstring).

    ``added`` / ``removed``: the list's writes to the asserted graph since ``after`` (its
    previous delta of this reference); ``pending_*`` and ``cleared``: all its net changes to
    the asserted graph.
    """
    try:
        prepared = prepare_delta(
            store,
            asserted=reference.asserted,
            inferred=reference.inferred,
            reasoner=reference.reasoner,
            changes=AssertedChanges(added=_triples(added), removed=_triples(removed)),
            pending=PendingChanges(
                added=_triples(pending_added),
                removed=_triples(pending_removed),
                cleared=cleared,
            ),
            after=after,
            recompute=recompute,
        )
    except ReasonerError as error:
        raise ReasonerFailure(f"REASON on {reference.name}: {error}") from None
    _log_clashes(reference, prepared.clashes)
    return prepared


def record_committed(
    store: Store, reference: Reference, *, added: Sequence[Quad], removed: Sequence[Quad] = ()
) -> None:
    """Tell the reasoner what a list asserted and retracted without reasoning over it: the next
    REASON derives the consequences of the additions and re-derives the part of the closure
    that the retractions touch, instead of recomputing it all."""
    record(
        store,
        asserted=reference.asserted,
        inferred=reference.inferred,
        changes=AssertedChanges(added=_triples(added), removed=_triples(removed)),
    )


def forget_state(store: Store, reference: Reference) -> None:
    """Make the next REASON of ``reference`` recompute (a DROP, a direct write)."""
    forget(store, asserted=reference.asserted, inferred=reference.inferred)
