"""REASON (OWL 2 RL materialisation into a reference's inferred graph) against owlrl, in one run.

What it measures, on synthetic scene ontologies (``reasoners.owl_rl.synthetic``: subclass
chains, defined classes with existential, data-range, value and intersection restrictions,
inverse / symmetric / transitive properties, data properties) of about 10k and 50k triples:

1. Full REASON: ``materialise()`` on a fresh store (in memory; on disk, as served, with
   ``--disk``) holding the ontology in the asserted graph: reading the graph, the closure, and
   the one all-or-nothing write of every inferred triple (bulk loaded, see
   ``kg.Store.fill_graph``), all timed.
2. owlrl 7.6.2: ``DeductiveClosure(OWLRL_Semantics).expand()`` on an rdflib ``Graph`` parsed
   from the same N-Triples (parsing not timed). By default at 10k only (about 25 s a run);
   ``--owlrl-50k`` adds 50k (about 2 minutes a run). Nothing is extrapolated: a size without an
   owlrl run prints no ratio. The ratio is owlrl ÷ REASON within the same round, where REASON
   is the median of three runs made just before and after the owlrl run (the machine is
   shared, so single runs are noisy).
3. Identity: the inferred graph against owlrl's additions, with owlrl's out-of-scope output
   filtered exactly as ``tests/reasoners/owl_rl/conftest.py`` documents (literal subjects,
   ``x owl:sameAs x``, its datatype disjointness axioms and error report).
4. Incremental REASON on the 50k reference: after a full REASON, ``--incremental`` times one
   transaction of 5 new assertions (a new object: type, scene, score, level, a relation) is
   written (not timed), then ``materialise()`` is timed: first given the 5 triples
   (``changes=``, what the directive layer passes after its directives), then without them (the
   reasoner reads the asserted graph and compares). At the end the incremental result is
   compared with a full REASON of the same asserted graph on a fresh store.
5. REASONs on the reasoned reference (``--recompute`` runs each): after 1 listed retraction of
   a type triple (re-derived in its region, :mod:`reasoners.owl_rl.retract`), after 1 listed
   retraction with the whole closure recomputed (the path schema retractions take), after a
   restart (no state in memory), and a second REASON with nothing changed; at the end the
   inferred graph is compared with a fresh full REASON's.

Run from the repository root::

    .venv/bin/python bench/reasoning.py                  # 10k + 50k, owlrl at 10k, 3 rounds
    .venv/bin/python bench/reasoning.py --owlrl-50k      # owlrl at 50k too (slow)
    .venv/bin/python bench/reasoning.py --repeats 1 --incremental 10
    .venv/bin/python bench/reasoning.py --disk --sizes 50000 --owlrl-50k   # as served
    .venv/bin/python bench/reasoning.py --disk --sizes 50000 --owlrl-50k --compare-unstreamed
"""

import argparse
import atexit
import os
import platform
import shutil
import statistics
import sys
import tempfile
import time
from collections.abc import Iterator
from contextlib import contextmanager

import owlrl
import rdflib
from owlrl.AxiomaticTriples import OWLRL_Datatypes_Disjointness
from pyoxigraph import Literal, NamedNode, RdfFormat, parse
from rdflib.namespace import OWL, RDF

from kg import Store
from ontologies.vocab import reference_graph
from reasoners.owl_rl import AssertedChanges, ReasonReport, forget, materialise
from reasoners.owl_rl.synthetic import EX, scene_ontology

ASSERTED = reference_graph("bench")
INFERRED = reference_graph("bench", inferred=True)
XSD = "http://www.w3.org/2001/XMLSchema#"
_ERRORS = "http://www.daml.org/2002/03/agents/agent-ont#"


_DISK: list[str] = []  # a directory for on-disk stores (--disk), else in-memory stores


def _store(document: bytes) -> Store:
    store = Store(tempfile.mkdtemp(dir=_DISK[0])) if _DISK else Store()
    with store.transaction() as tx:
        tx.load(document, format=RdfFormat.N_TRIPLES, graph=ASSERTED)
    return store


def _inferred(store: Store) -> set[str]:
    return {f"{q.subject} {q.predicate} {q.object}" for q in store.quads(graph=INFERRED)}


def owlrl_closure(asserted: bytes) -> tuple[float, set[str]]:
    """owlrl's closure time and additions, minus what tests/reasoners/owl_rl filters."""
    graph = rdflib.Graph()
    graph.parse(data=asserted, format="nt")
    before = set(graph)
    start = time.perf_counter()
    owlrl.DeductiveClosure(owlrl.OWLRL_Semantics).expand(graph)
    elapsed = time.perf_counter() - start
    kept = rdflib.Graph()
    for s, p, o in set(graph) - before:
        if isinstance(s, rdflib.Literal | rdflib.BNode) or (p == OWL.sameAs and s == o):
            continue
        if (s, p, o) in OWLRL_Datatypes_Disjointness or str(p).startswith(_ERRORS):
            continue
        kept.add((s, p, o))
    text = kept.serialize(format="nt", encoding="utf-8")
    triples = parse(text, format=RdfFormat.N_TRIPLES)
    return elapsed, {f"{t.subject} {t.predicate} {t.object}" for t in triples}


def _full(document: bytes, *, streamed: bool = True) -> tuple[float, ReasonReport, Store]:
    """A full REASON on a fresh store; ``streamed=False`` writes the closure after deriving
    it (the path before the closure was streamed to the bulk loader), for comparison."""
    store = _store(document)
    module = sys.modules[materialise.__module__]
    stream_min = module._STREAM_MIN  # type: ignore[attr-defined]
    if not streamed:
        module._STREAM_MIN = 10**12  # type: ignore[attr-defined]
    try:
        start = time.perf_counter()
        report = materialise(store, asserted=ASSERTED, inferred=INFERRED)
        return time.perf_counter() - start, report, store
    finally:
        module._STREAM_MIN = stream_min  # type: ignore[attr-defined]


def _new_object(store: Store, n: int) -> list[tuple[NamedNode, NamedNode, NamedNode | Literal]]:
    """Assert 5 triples about a new object in one transaction; return them."""
    obj, scene = NamedNode(f"{EX}bench_obj{n}"), NamedNode(f"{EX}scene{n % 100}")
    double, integer = NamedNode(XSD + "double"), NamedNode(XSD + "integer")
    triples: list[tuple[NamedNode, NamedNode, NamedNode | Literal]] = [
        (obj, NamedNode(str(RDF.type)), NamedNode(EX + "Mug")),
        (obj, NamedNode(EX + "inScene"), scene),
        (obj, NamedNode(EX + "score"), Literal("0.5", datatype=double)),
        (obj, NamedNode(EX + "level"), Literal("0", datatype=integer)),
        (obj, NamedNode(EX + "above"), NamedNode(f"{EX}scene{n % 100}_obj0")),
    ]
    with store.transaction() as tx:
        for s, p, o in triples:
            tx.insert(s, p, o, ASSERTED)
    return triples


def _recomputations(store: Store, runs: int) -> dict[str, list[float]]:
    """Full REASONs (the whole closure computed again) on a reference already reasoned, as
    served: ``runs`` times each of

    - "retraction": one asserted triple retracted (a different one each time), the caller
      listing it (``changes=``, as the directive layer does); the reasoner's state in memory;
    - "restart": no state in memory (``forget``, as after a server restart), nothing changed:
      both graphs are read;
    - "unchanged": a second REASON with nothing changed (state in memory).
    """
    times: dict[str, list[float]] = {
        "retraction": [],
        "retraction_whole": [],
        "restart": [],
        "unchanged": [],
    }
    types = [q for q in store.quads(None, NamedNode(str(RDF.type)), None, ASSERTED)]
    for n in range(runs):
        quad = types[(n * 7919) % len(types)]
        triple = (quad.subject, quad.predicate, quad.object)
        with store.transaction() as tx:
            tx.delete(*triple, ASSERTED)  # type: ignore[arg-type]
        changes = AssertedChanges(removed=[triple])  # type: ignore[list-item]
        start = time.perf_counter()
        report = materialise(store, asserted=ASSERTED, inferred=INFERRED, changes=changes)
        times["retraction"].append(time.perf_counter() - start)
        assert report.scoped, "expected a retraction re-derived in its region"
        quad = types[(n * 7919 + 1) % len(types)]
        triple = (quad.subject, quad.predicate, quad.object)
        with store.transaction() as tx:
            tx.delete(*triple, ASSERTED)  # type: ignore[arg-type]
        changes = AssertedChanges(removed=[triple])  # type: ignore[list-item]
        with _whole_recomputation():
            start = time.perf_counter()
            report = materialise(store, asserted=ASSERTED, inferred=INFERRED, changes=changes)
            times["retraction_whole"].append(time.perf_counter() - start)
        assert not (report.incremental or report.scoped), "expected a whole recomputation"
        forget(store, asserted=ASSERTED, inferred=INFERRED)
        start = time.perf_counter()
        report = materialise(store, asserted=ASSERTED, inferred=INFERRED)
        times["restart"].append(time.perf_counter() - start)
        assert (report.incremental, report.added, report.removed) == (False, 0, 0)
        start = time.perf_counter()
        report = materialise(store, asserted=ASSERTED, inferred=INFERRED)
        times["unchanged"].append(time.perf_counter() - start)
    return times


@contextmanager
def _whole_recomputation() -> Iterator[None]:
    """Make a listed retraction recompute the whole closure (the path before regions)."""
    module = sys.modules[materialise.__module__]
    scoped = module._retract_listed
    module._retract_listed = lambda *args: None  # type: ignore[attr-defined]
    try:
        yield
    finally:
        module._retract_listed = scoped  # type: ignore[attr-defined]


def _incremental(store: Store, runs: int, *, with_list: bool) -> None:
    times, added = [], []
    for n in range(runs):
        triples = _new_object(store, n + (10_000 if with_list else 0))
        start = time.perf_counter()
        changes = AssertedChanges(added=triples) if with_list else None
        report = materialise(store, asserted=ASSERTED, inferred=INFERRED, changes=changes)
        times.append(time.perf_counter() - start)
        added.append(report.added)
        assert report.incremental, "expected an incremental REASON"
    times.sort()
    p95 = times[min(len(times) - 1, int(0.95 * len(times)))]
    how = "given the 5 added triples (changes=)" if with_list else "reading the asserted graph"
    print(
        f"incremental REASON after 5 new assertions, {how}, {len(times)} runs: median "
        f"{1000 * statistics.median(times):.1f} ms, p95 {1000 * p95:.1f} ms, max "
        f"{1000 * times[-1]:.1f} ms ({statistics.median(added):.0f} inferred triples added)"
    )


def _print_recomputations(store: Store, runs: int, baseline: float | None) -> None:
    labels = {
        "retraction": (
            "REASON after 1 retraction (changes= listed, state in memory; re-derives the"
            " retracted triple's region, see reasoners/owl_rl/retract.py)"
        ),
        "retraction_whole": (
            "full REASON after 1 retraction, whole closure recomputed (changes= listed, state"
            " in memory; the path for schema retractions)"
        ),
        "restart": "full REASON after a restart (no state; reads both graphs, writes nothing)",
        "unchanged": "second REASON, nothing changed",
    }
    for kind, times in _recomputations(store, runs).items():
        median = statistics.median(times)
        line = f"  {labels[kind]}: median {median * 1000:.1f} ms of {len(times)}"
        if baseline is not None and median > 0:
            line += f" | owlrl ÷ it: {baseline / median:.0f}"
        print(line, flush=True)
    _, _, fresh = _full(store.graph_ntriples(ASSERTED))
    same = _inferred(store) == _inferred(fresh)
    print(f"  after them, the inferred graph equals a fresh full REASON's: {same}", flush=True)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--repeats", type=int, default=3, help="rounds of full REASON per size")
    parser.add_argument("--owlrl-runs", type=int, default=1, help="owlrl runs per size (slow)")
    parser.add_argument("--owlrl-50k", action="store_true", help="run owlrl at 50k as well")
    parser.add_argument("--incremental", type=int, default=20, help="incremental REASONs at 50k")
    parser.add_argument("--sizes", default="10000,50000", help="ontology sizes in triples")
    parser.add_argument("--disk", action="store_true", help="on-disk stores (as served)")
    parser.add_argument(
        "--recompute",
        type=int,
        default=3,
        help="full REASONs on a reasoned reference per kind (retraction, restart, unchanged)",
    )
    parser.add_argument(
        "--compare-unstreamed",
        action="store_true",
        help="also time each round's REASON writing its closure after deriving it",
    )
    args = parser.parse_args()
    if args.disk:
        _DISK.append(tempfile.mkdtemp(prefix="engram-bench-"))
        atexit.register(shutil.rmtree, _DISK[0], True)
    sizes = [int(s) for s in args.sizes.split(",")]
    python = platform.python_version()
    kind = "on-disk" if args.disk else "in-memory"
    print(f"# REASON ({kind} stores) vs owlrl {owlrl.__version__}: Python {python}, ", end="")
    print(f"{os.cpu_count()} CPUs, load average {os.getloadavg()[0]:.2f}")

    for size in sizes:
        document = ("\n".join(scene_ontology(size, seed=1)) + "\n").encode()
        triples = _store(document).graph_ntriples(ASSERTED).count(b"\n")
        with_owlrl = size <= 10_000 or args.owlrl_50k
        print(f"\n## {triples} asserted triples")
        ours, ratios, store, baseline = [], [], None, 0.0
        for round_ in range(args.repeats):
            owlrl_round = with_owlrl and round_ < args.owlrl_runs
            runs = []
            for _ in range(3 if owlrl_round else 1):  # around the baseline: the median of 3
                elapsed, report, store = _full(document)
                runs.append(elapsed)
                if owlrl_round and len(runs) == 2:
                    baseline, expected = owlrl_closure(
                        store.graph_ntriples(ASSERTED)
                    )  # same skolem IRIs
                    same = _inferred(store) == expected
            elapsed = statistics.median(runs)
            ours.append(elapsed)
            line = f"round {round_ + 1}: REASON {elapsed:.3f} s (+{report.added} inferred)"
            if args.compare_unstreamed:
                before, before_report, _ = _full(document, streamed=False)
                assert before_report.added == report.added
                line += f" | unstreamed write {before:.3f} s"
                if owlrl_round:
                    line += f" (ratio {baseline / before:.0f})"
            if owlrl_round:
                ratios.append(baseline / elapsed)
                line += f" | owlrl {baseline:.2f} s | ratio {baseline / elapsed:.0f}"
                line += f" | identical: {same}"
                line += f" | REASON runs around it: {', '.join(f'{r:.3f}' for r in runs)}"
            print(line, flush=True)
            if args.recompute and store is not None and round_ == 0:
                _print_recomputations(store, args.recompute, baseline if owlrl_round else None)
        print(f"REASON median {statistics.median(ours):.3f} s over {len(ours)} rounds", end="")
        print(
            f"; owlrl ÷ REASON per round: {', '.join(f'{r:.0f}' for r in ratios)}"
            if ratios
            else "; owlrl not run at this size"
        )

        if size == max(sizes) and args.incremental and store is not None:
            _incremental(store, args.incremental, with_list=True)
            _incremental(store, args.incremental, with_list=False)
            _, _, fresh = _full(store.graph_ntriples(ASSERTED))
            print(
                f"incremental result equals a full REASON: {_inferred(store) == _inferred(fresh)}"
            )


if __name__ == "__main__":
    main()
