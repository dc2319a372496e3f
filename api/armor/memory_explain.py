"""``QUERY MEMORY EXPLAIN [class, scene item or forgotten IRI]``: why the memory decided what it
did about it (see :mod:`reasoners.explain`).

The answer's ``queried_objects`` are the explanations in words, one per kind; its
``sparql_queried_objects`` carry each as ``kind`` → words, and ``json`` → all of them as one
JSON array.
"""

import json

from api.armor.context import Context, Outcome
from api.armor.errors import MemoryDirectiveError
from api.armor.names import resolve
from api.protocol import QueryItem
from ontologies.vocab import ENGRAM_NS
from reasoners.errors import MemoryReasonerError
from reasoners.explain import explain, to_jsonable

__all__ = ["query_memory_explain"]


def query_memory_explain(ctx: Context) -> Outcome:
    """Explain a live class or experienced scene, or something in the trash."""
    iri = resolve(
        ctx.arg(0, "class, scene item or forgotten IRI"), ENGRAM_NS.rstrip("#"), field="args[0]"
    )
    try:
        explanations = explain(ctx.scene_memory(), iri)
    except (MemoryReasonerError, ValueError) as error:
        raise MemoryDirectiveError(f"args[0]: {error}") from None
    bodies = [to_jsonable(e) for e in explanations]
    pairs = [QueryItem(key=e.kind, value=e.words) for e in explanations]
    pairs.append(QueryItem(key="json", value=json.dumps(bodies)))
    return Outcome(queried_objects=[e.words for e in explanations], sparql_queried_objects=pairs)
