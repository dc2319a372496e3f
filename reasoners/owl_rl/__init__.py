"""OWL 2 RL and DL-safe SWRL reasoning for ARMOR references: REASON and consistency.

:func:`materialise` writes the closure of a reference's asserted graph into its inferred graph
(one transaction; incremental after additions, fastest when the caller passes
``changes=AssertedChanges(added=[...])``; a listed retraction of instance triples re-derives
only the region of the closure it touches, :mod:`reasoners.owl_rl.retract`; other retractions
recompute), :func:`is_consistent` checks the OWL 2 RL inconsistency rules and names the
clashes, :func:`forget` drops the reasoner's memory of a reference (call it after writing its
inferred graph by other means), :func:`record` notes assertions and retractions committed
without a REASON, and :func:`prepare` computes the inferred graph's delta for a writer's
uncommitted changes without writing it (the writer commits it with its own transaction;
:mod:`reasoners.owl_rl.pending`). ARMOR's reasoner names (``PELLET``,
``HERMIT``, ``FACT``, ``SNOROCKET``, any case, and ``OWL2RL``) are aliases of this one engine.

What is inferred: every rule of the OWL 2 RL/RDF tables (W3C OWL 2 Profiles, section 4.3):
equality (eq-sym, eq-trans, eq-rep-s/p/o), property axioms (prp-dom, prp-rng, prp-fp, prp-ifp,
prp-symp, prp-trp, prp-spo1, prp-spo2 chains, prp-eqp1/2, prp-inv1/2, prp-key), class expressions
(cls-thing, cls-nothing1, cls-int1/2, cls-uni, cls-svf1/2, cls-avf, cls-hv1/2, cls-maxc2,
cls-maxqc3/4, cls-oo), class axioms (cax-sco, cax-eqc1/2), the schema rules (scm-cls, scm-sco,
scm-eqc1/2, scm-op, scm-dp, scm-spo, scm-eqp1/2, scm-dom1/2, scm-rng1/2, scm-hv, scm-svf1/2,
scm-avf1/2, scm-int, scm-uni), prp-ap, and the datatype rules (dt-type1, dt-type2 by value space,
dt-eq; :mod:`reasoners.owl_rl.datatypes`). Consistency: cls-nothing2, cax-dw, cax-adc, cls-com,
eq-diff1/2/3, prp-irp, prp-asyp, prp-pdw, prp-adp, prp-npa1/2, cls-maxc1, cls-maxqc1/2,
dt-diff, dt-not-type. Plus the DL-safe SWRL rules in the asserted graph, with the built-ins
listed in :mod:`reasoners.owl_rl.swrl`.

Not written to the inferred graph, by design (docs/owl-rl.md lists each with its test): triples
with a literal subject (RDF cannot hold them; dt-type2's ``"1"^^xsd:integer rdf:type
xsd:integer`` and dt-eq's literal ``owl:sameAs`` stay inside the engine, where the rules use
them), ``x owl:sameAs x`` (eq-ref, true of every term), and dt-diff's ``owl:differentFrom``
between every two literals of different values (quadratic; checked as a clash instead).
A literal typed only for the rules is typed with the datatypes the schema names.

Outside OWL 2 RL, so never inferred (a DL reasoner such as Pellet or HermiT would):
membership from a minimum or exact cardinality (``≥ 3 hasObject.Graspable``), existentials on
the right of a subclass axiom (``Cup ⊑ ∃hasHandle.Handle`` creates no anonymous handle),
disjunction on the right (``A ⊑ B ⊔ C``) and reasoning by cases, complement used to classify
(``¬A``), universal restrictions on the left, ``owl:maxCardinality`` above 1, nominals beyond
``owl:oneOf`` membership, reflexive properties (``owl:ReflexiveProperty``, ``owl:hasSelf``),
datatype facets and data-range reasoning beyond literal types, and the entailments that need
the unique-name assumption to be dropped on purpose. Everything is open-world and
monotonic: nothing is concluded from the absence of a triple.

>>> sorted(REASONER_NAMES)[:3]
['', 'fact', 'hermit']
"""

from reasoners.owl_rl.consistency import Clash
from reasoners.owl_rl.errors import ReasonerError, SwrlRuleError, UnknownReasonerError
from reasoners.owl_rl.materialise import (
    REASONER_NAMES,
    AssertedChanges,
    ConsistencyReport,
    ReasonReport,
    closure,
    forget,
    is_consistent,
    materialise,
    record,
)
from reasoners.owl_rl.pending import PendingChanges, Prepared, prepare

__all__ = [
    "REASONER_NAMES",
    "AssertedChanges",
    "Clash",
    "ConsistencyReport",
    "PendingChanges",
    "Prepared",
    "ReasonReport",
    "ReasonerError",
    "SwrlRuleError",
    "UnknownReasonerError",
    "closure",
    "forget",
    "is_consistent",
    "materialise",
    "prepare",
    "record",
]
