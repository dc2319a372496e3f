"""What an export adds to the experienced scenes so that a DL reasoner can classify them.

The store keeps a scene's primitives and the primary relations between them; a learned class is
defined on scene-level links (``scene sphereIsAboveOf o``). For each exported scene the export
adds those links (from the stored relations and the T-Box's signature properties, as the
encoder derives them) and one ``owl:AllDifferent`` of its primitives, so that HermiT or Pellet
realises the scene into the class Engram stored it as (DESIGN.md, step 3).
"""

from pyoxigraph import BlankNode, NamedNode, Triple

from kg.store import Store
from ontologies.vocab import GRAPHS, OWL_NS, RDF_FIRST, RDF_NIL, RDF_REST, RDF_TYPE

__all__ = ["SCENE_GRAPHS", "scene_axioms"]

SCENE_GRAPHS = ("episodic", "trash")
"""The graphs whose experienced scenes get their links and AllDifferent axioms."""

_ALL_DIFFERENT = NamedNode(OWL_NS + "AllDifferent")
_DISTINCT_MEMBERS = NamedNode(OWL_NS + "distinctMembers")


def scene_axioms(store: Store, graph_name: str) -> list[Triple]:
    """The signature links and one AllDifferent per experienced scene of graph ``graph_name``."""
    graph = GRAPHS[graph_name]
    out = [
        Triple(row["scene"], row["property"], row["object"])  # type: ignore[arg-type]
        for row in store.select("export_scene_links", g=graph)
    ]
    members: dict[NamedNode, list[NamedNode]] = {}
    for row in store.select("export_scene_primitives", g=graph):
        members.setdefault(row["scene"], []).append(row["primitive"])  # type: ignore[arg-type]
    for primitives in members.values():
        if len(primitives) < 2:
            continue
        head: NamedNode | BlankNode = RDF_NIL
        for primitive in reversed(primitives):
            cell = BlankNode()
            out += [Triple(cell, RDF_FIRST, primitive), Triple(cell, RDF_REST, head)]
            head = cell
        axiom = BlankNode()
        out += [Triple(axiom, RDF_TYPE, _ALL_DIFFERENT), Triple(axiom, _DISTINCT_MEMBERS, head)]
    return out
