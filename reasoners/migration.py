"""Migrating a store written before docs/data-model.md, once, when the memory opens.

Before, every sleep pass wrote each class's and experienced scene's level
(``engram:sleepLevel``) and the score view packed Z_d, Z_s, Z_r in one string
(``engram:scoreTerms``); a WEAK count of 0 was written once a count fell back; and the trash kept
the WEAK count of the pass before the one that forgot (k - 1 for a class forgotten at its k-th
WEAK pass). :func:`migrate` rewrites that into the current layout in the transaction
:meth:`reasoners.score_view.ScoreView.repair` opens; :func:`needed` says whether there is
anything to do (a few index lookups). In the history, a sleep pass's events packed in one
literal (``engram:historyPassEntries``, zlib + base64) become the plain text that SPARQL reads
(``engram:historyPassEvents``); events with one ``engram:eventParent`` per parent and per-class
``level`` event nodes are read as they are.
"""

import logging

from pyoxigraph import Literal

from kg.store import Store
from kg.transaction import Transaction
from ontologies.vocab import (
    CONSECUTIVE_WEAK_COUNT,
    EPISODIC,
    HISTORY,
    HISTORY_PASS_ENTRIES,
    HISTORY_PASS_EVENTS,
    LEVEL,
    MEMORY,
    MEMORY_STATE_INDIVIDUAL,
    SCORE_TERMS,
    SLEEP_LEVELS,
    TRASH,
)
from reasoners import history, persist
from reasoners.model import MemoryModel
from reasoners.scoring import WEAK

__all__ = ["migrate", "needed"]

log = logging.getLogger(__name__)


def _levels_kept(store: Store) -> bool:
    return any(True for _ in store.quads(MEMORY_STATE_INDIVIDUAL, SLEEP_LEVELS, None, MEMORY))


def needed(store: Store, model: MemoryModel) -> bool:
    """Whether ``store`` holds what a memory before docs/data-model.md wrote: levels or packed
    score terms on items, zero WEAK counts, sleep passes without the levels literal, or a
    pass's history events packed."""
    found = (
        (None, HISTORY_PASS_ENTRIES, None, HISTORY),
        (None, LEVEL, None, MEMORY),
        (None, LEVEL, None, EPISODIC),
        (None, SCORE_TERMS, None, MEMORY),
        (None, CONSECUTIVE_WEAK_COUNT, Literal(0), MEMORY),
        (None, CONSECUTIVE_WEAK_COUNT, Literal(0), EPISODIC),
    )
    if any(True for pattern in found for _ in store.quads(*pattern)):
        return True
    return model.state.sleep_passes > 0 and not _levels_kept(store)


def migrate(tx: Transaction, store: Store, model: MemoryModel) -> None:
    """Bring ``store`` (read into ``model``) to docs/data-model.md, in ``tx``: the levels of the
    last sleep pass move from each item to the memory state's one literal; packed score terms
    become typed ones (the model's view is marked unwritten, so the transaction writes it
    whole); zero WEAK counts go; a class, or an experienced scene forgotten alone, in the trash
    from then gets the WEAK count and level that forgot it (a scene forgotten with its class
    keeps its own); each sleep pass's packed history events become its plain text."""
    if not _levels_kept(store) and model.state.sleep_passes > 0:
        with_class = {
            iri
            for iri, t in model.trash.items.items()
            if t.cls in model.trash.classes
            and model.trash.classes[t.cls].forgotten_at == t.forgotten_at
        }
        alone = [i for i in model.trash.items if i not in with_class]
        for entry in sorted([*model.trash.classes, *alone], key=str):
            count = next(store.quads(entry, CONSECUTIVE_WEAK_COUNT, None, TRASH), None)
            before = int(persist.text(count.object)) if count is not None else 0
            tx.delete_matching(entry, CONSECUTIVE_WEAK_COUNT, None, graph=TRASH)
            tx.insert(entry, CONSECUTIVE_WEAK_COUNT, Literal(before + 1), TRASH)
            tx.delete_matching(entry, LEVEL, None, graph=TRASH)
            tx.insert(entry, LEVEL, Literal(WEAK), TRASH)
    for graph in (MEMORY, EPISODIC):
        tx.delete_matching(None, LEVEL, None, graph=graph)
        tx.delete_matching(None, CONSECUTIVE_WEAK_COUNT, Literal(0), graph=graph)
    if model.state.sleep_passes > 0:
        persist.write_levels(tx, model)
    if any(True for _ in store.quads(None, SCORE_TERMS, None, MEMORY)):
        tx.delete_matching(None, SCORE_TERMS, None, graph=MEMORY)
        for record in model.graph.classes.values():
            record.written_z = None
        model.scores.unwritten.update(model.graph.classes)
    for quad in store.quads(None, HISTORY_PASS_ENTRIES, None, HISTORY):
        entries = history._unpack(quad.object)
        if entries:
            tx.insert(quad.subject, HISTORY_PASS_EVENTS, history.pass_text(entries), HISTORY)  # type: ignore[arg-type]
        tx.delete(quad.subject, HISTORY_PASS_ENTRIES, quad.object, HISTORY)  # type: ignore[arg-type]
    log.info("scene memory: store migrated to the data model of docs/data-model.md")
