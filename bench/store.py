"""Engram's store next to rdflib's in-memory ``Graph``, on the same synthetic scenes, in one run.

What it measures:

1. Insert throughput (quads/s) of
   - Engram in memory (``Store()``) and on disk (``Store(path)`` in a temporary directory), each
     written through ``store.transaction()`` once with one transaction per scene (the realistic
     write path: one transaction per perceived scene) and once as one big transaction;
   - rdflib ``Graph.add`` of the same triples, one call per triple.
   Only the writes are timed: building the terms (pyoxigraph terms for Engram, rdflib terms for
   rdflib) and opening the store happen before the clock starts. On-disk writes are timed up to
   the commit (data visible to readers), without ``Store.flush()``.
2. SPARQL latency (median and p95, microseconds) of a point lookup ("the centreX of primitive X",
   ``bench/queries/point_lookup.rq``) and a 3-pattern join ("the spheres of scene S with their
   radius", ``bench/queries/scene_join.rq``), each with one bound term: Engram through a
   ``select``-equivalent call with bindings, rdflib through ``Graph.query`` on a query prepared
   once with ``prepareQuery`` and passed ``initBindings``. Both sides build a list of dicts.

Machines are noisy, so every measurement is repeated ``--repeats`` times, the engines take turns
within each round (and the starting engine rotates), and the tables show every round, the median
and the per-round ratios.

Run from the repository root::

    .venv/bin/python bench/store.py                 # 2,000 scenes, 3 rounds
    .venv/bin/python bench/store.py --scenes 500 --repeats 5
"""

import argparse
import gc
import os
import platform
import random
import statistics
import tempfile
import time
from collections.abc import Callable
from itertools import combinations
from pathlib import Path
from typing import Any

import pyoxigraph
import rdflib
from pyoxigraph import Literal, NamedNode
from rdflib.plugins.sparql import prepareQuery

import sparql
from kg.store import Binding, Store
from ontologies.vocab import ENGRAM_NS, EPISODIC, PRIMITIVE_LEAF_TYPES, RDF_TYPE, SCENE, SPHERE

QUERIES = Path(__file__).resolve().parent / "queries"
HAS_PRIMITIVE = ENGRAM_NS + "hasPrimitive"  # benchmark data only; not an Engram property
NUMERIC_PROPERTIES = [ENGRAM_NS + name for name in ("centreX", "centreY", "centreZ", "radius")]
RELATIONS = [ENGRAM_NS + name for name in ("isAboveOf", "isRightOf", "isInFrontOf")]
SEED = 20240611
WARMUP = 20

Raw = tuple[str, str, str | float]  # subject IRI, predicate IRI, object IRI or xsd:double value


class BenchStore(Store):
    """Engram's Store with one extra read method, :meth:`select_text`.

    The benchmark's queries are not part of Engram's query set (``sparql/``), so
    ``Store.select(name)`` cannot load them; ``select_text`` runs a query text through the very
    code path ``select`` uses (binding, tracing, union default graph, rows as dicts).
    """

    def select_text(self, text: str, **bindings: Binding) -> list[dict[str, Binding]]:
        return self._select(text, bindings)


# Synthetic data ------------------------------------------------------------------------------


def make_scenes(count: int, seed: int) -> list[list[Raw]]:
    """``count`` scenes of 4-6 typed primitives with centre, radius and two spatial relations."""
    rng = random.Random(seed)
    scenes = []
    for i in range(count):
        scene = f"{ENGRAM_NS}Scene-{i}"
        triples: list[Raw] = [(scene, RDF_TYPE.value, SCENE.value)]
        primitives = [f"{ENGRAM_NS}Primitive-{i}-{j}" for j in range(rng.randint(4, 6))]
        for primitive in primitives:
            triples.append((scene, HAS_PRIMITIVE, primitive))
            triples.append((primitive, RDF_TYPE.value, rng.choice(PRIMITIVE_LEAF_TYPES).value))
            for prop in NUMERIC_PROPERTIES:
                triples.append((primitive, prop, round(rng.uniform(-1.0, 1.0), 4)))
        for a, b in rng.sample(list(combinations(primitives, 2)), 2):
            triples.append((a, rng.choice(RELATIONS), b))
        scenes.append(triples)
    return scenes


def to_engram(scenes: list[list[Raw]]) -> list[list[tuple[Any, Any, Any]]]:
    iris: dict[str, NamedNode] = {}

    def iri(value: str) -> NamedNode:
        node = iris.get(value)
        if node is None:
            node = iris[value] = NamedNode(value)
        return node

    return [
        [(iri(s), iri(p), Literal(o) if isinstance(o, float) else iri(o)) for s, p, o in scene]
        for scene in scenes
    ]


def to_rdflib(scenes: list[list[Raw]]) -> list[list[tuple[Any, Any, Any]]]:
    iris: dict[str, rdflib.URIRef] = {}

    def iri(value: str) -> rdflib.URIRef:
        node = iris.get(value)
        if node is None:
            node = iris[value] = rdflib.URIRef(value)
        return node

    return [
        [
            (iri(s), iri(p), rdflib.Literal(o) if isinstance(o, float) else iri(o))
            for s, p, o in scene
        ]
        for scene in scenes
    ]


# Writers (the timed bodies) ------------------------------------------------------------------


def engram_per_scene(store: Store, scenes: list[list[tuple[Any, Any, Any]]]) -> None:
    for scene in scenes:
        with store.transaction() as tx:
            for s, p, o in scene:
                tx.insert(s, p, o, EPISODIC)


def engram_one_tx(store: Store, scenes: list[list[tuple[Any, Any, Any]]]) -> None:
    with store.transaction() as tx:
        for scene in scenes:
            for s, p, o in scene:
                tx.insert(s, p, o, EPISODIC)


def rdflib_add(graph: rdflib.Graph, scenes: list[list[tuple[Any, Any, Any]]]) -> None:
    add = graph.add
    for scene in scenes:
        for triple in scene:
            add(triple)


# Helpers -------------------------------------------------------------------------------------


def rotated(items: list[Any], shift: int) -> list[Any]:
    shift %= len(items)
    return items[shift:] + items[:shift]


def p95(values: list[float]) -> float:
    ordered = sorted(values)
    return ordered[min(len(ordered) - 1, round(0.95 * (len(ordered) - 1)))]


def filesystem_of(path: str) -> str:
    """Best effort: the type of the file system holding ``path`` (Linux only)."""
    try:
        mounts = [line.split() for line in Path("/proc/mounts").read_text().splitlines()]
    except OSError:
        return "unknown"
    real = os.path.realpath(path)
    best = ("", "unknown")
    for fields in mounts:
        point = fields[1]
        inside = real == point or real.startswith(point.rstrip("/") + "/")
        if inside and len(point) > len(best[0]):
            best = (point, fields[2])
    return best[1]


def fmt_rate(value: float) -> str:
    return f"{value:,.0f}"


def fmt_ratio(value: float) -> str:
    return f"{value:.2f}x"


def print_table(header: list[str], rows: list[list[str]]) -> None:
    widths = [max(len(row[i]) for row in [header, *rows]) for i in range(len(header))]

    def line(cells: list[str]) -> str:
        padded = [cells[0].ljust(widths[0])]
        padded += [c.rjust(w) for c, w in zip(cells[1:], widths[1:], strict=True)]
        return "  ".join(padded)

    print(line(header))
    print("-" * len(line(header)))
    for row in rows:
        print(line(row))


# Insert benchmark ----------------------------------------------------------------------------


def bench_inserts(
    ox_scenes: list[list[tuple[Any, Any, Any]]],
    rdf_scenes: list[list[tuple[Any, Any, Any]]],
    quads: int,
    repeats: int,
    tmp_root: str | None,
) -> None:
    def engram_case(on_disk: bool, writer: Callable[..., None]) -> Callable[[], float]:
        def run() -> float:
            with tempfile.TemporaryDirectory(prefix="engram-bench-", dir=tmp_root) as tmp:
                store = BenchStore(Path(tmp) / "store") if on_disk else BenchStore()
                gc.collect()
                start = time.perf_counter()
                writer(store, ox_scenes)
                elapsed = time.perf_counter() - start
                if len(store) != quads:
                    raise AssertionError(f"Engram holds {len(store)} quads, expected {quads}")
                del store
                gc.collect()
            return elapsed

        return run

    def rdflib_case() -> float:
        graph = rdflib.Graph()
        gc.collect()
        start = time.perf_counter()
        rdflib_add(graph, rdf_scenes)
        elapsed = time.perf_counter() - start
        if len(graph) != quads:
            raise AssertionError(f"rdflib holds {len(graph)} triples, expected {quads}")
        return elapsed

    cases: dict[str, Callable[[], float]] = {
        "Engram memory, 1 tx/scene": engram_case(False, engram_per_scene),
        "Engram memory, 1 big tx": engram_case(False, engram_one_tx),
        "Engram disk, 1 tx/scene": engram_case(True, engram_per_scene),
        "Engram disk, 1 big tx": engram_case(True, engram_one_tx),
        "rdflib Graph.add": rdflib_case,
    }
    rates: dict[str, list[float]] = {name: [] for name in cases}
    for round_ in range(repeats):
        for name in rotated(list(cases), round_):
            rates[name].append(quads / cases[name]())

    reference = rates["rdflib Graph.add"]
    header = [
        "engine",
        *[f"round {r + 1}" for r in range(repeats)],
        "median",
        "Engram/rdflib per round",
        "median ratio",
    ]
    rows = []
    for name, values in rates.items():
        ratios = [v / ref for v, ref in zip(values, reference, strict=True)]
        is_ref = name == "rdflib Graph.add"
        rows.append(
            [
                name,
                *[fmt_rate(v) for v in values],
                fmt_rate(statistics.median(values)),
                "(reference)" if is_ref else " ".join(fmt_ratio(r) for r in ratios),
                "" if is_ref else fmt_ratio(statistics.median(ratios)),
            ]
        )
    print(f"Insert throughput, quads/s ({quads:,} quads; higher is better)")
    print_table(header, rows)


# Query benchmark -----------------------------------------------------------------------------


def bench_queries(
    raw: list[list[Raw]],
    ox_scenes: list[list[tuple[Any, Any, Any]]],
    rdf_scenes: list[list[tuple[Any, Any, Any]]],
    lookups: int,
    repeats: int,
    tmp_root: str | None,
) -> None:
    texts = {name: (QUERIES / f"{name}.rq").read_text(encoding="utf-8") for name in QUERY_SPECS}
    prepared = {name: prepareQuery(text) for name, text in texts.items()}

    rng = random.Random(SEED + 1)
    primitives = sorted({s for scene in raw for s, p, _ in scene if p == NUMERIC_PROPERTIES[0]})
    scenes = [scene[0][0] for scene in raw]
    keys = {
        "point_lookup": [rng.choice(primitives) for _ in range(lookups)],
        "scene_join": [rng.choice(scenes) for _ in range(lookups)],
    }

    with tempfile.TemporaryDirectory(prefix="engram-bench-", dir=tmp_root) as tmp:
        memory, disk = BenchStore(), BenchStore(Path(tmp) / "store")
        for store in (memory, disk):
            engram_one_tx(store, ox_scenes)
        graph = rdflib.Graph()
        rdflib_add(graph, rdf_scenes)
        # select_text must behave exactly like select on a product query.
        if memory.select_text(sparql.load("graph_sizes")) != memory.select("graph_sizes"):
            raise AssertionError("select_text disagrees with Store.select")

        def engram_runner(store: BenchStore, name: str) -> Callable[[str], int]:
            text, variable = texts[name], QUERY_SPECS[name]

            def run(key: str) -> int:
                return len(store.select_text(text, **{variable: NamedNode(key)}))

            return run

        def rdflib_runner(name: str) -> Callable[[str], int]:
            query, variable = prepared[name], QUERY_SPECS[name]

            def run(key: str) -> int:
                result = graph.query(query, initBindings={variable: rdflib.URIRef(key)})
                return len([row.asdict() for row in result])  # type: ignore[union-attr]

            return run

        for name in QUERY_SPECS:
            engines = {
                "Engram memory": engram_runner(memory, name),
                "Engram disk": engram_runner(disk, name),
                "rdflib Graph": rdflib_runner(name),
            }
            # Same answers everywhere (row counts), checked before any timing; also a warm-up.
            expected = [engines["Engram memory"](key) for key in keys[name]]
            for engine, run in engines.items():
                if [run(key) for key in keys[name]] != expected:
                    raise AssertionError(f"{engine} disagrees on {name}")
                for key in keys[name][:WARMUP]:
                    run(key)
            if name == "scene_join":
                truth = [
                    sum(1 for _, p, o in scene if p == RDF_TYPE.value and o == SPHERE.value)
                    for scene in raw
                ]
                index = {scene[0][0]: i for i, scene in enumerate(raw)}
                if expected != [truth[index[key]] for key in keys[name]]:
                    raise AssertionError("scene_join row counts do not match the data")
            rows_returned = sum(expected)

            medians: dict[str, list[float]] = {engine: [] for engine in engines}
            tails: dict[str, list[float]] = {engine: [] for engine in engines}
            for round_ in range(repeats):
                for engine in rotated(list(engines), round_):
                    run = engines[engine]
                    samples = []
                    gc.collect()
                    for key in keys[name]:
                        start = time.perf_counter()
                        run(key)
                        samples.append((time.perf_counter() - start) * 1e6)
                    medians[engine].append(statistics.median(samples))
                    tails[engine].append(p95(samples))

            reference = medians["rdflib Graph"]
            header = [
                "engine",
                *[f"median r{r + 1}" for r in range(repeats)],
                "median",
                "p95",
                "rdflib/Engram per round",
                "median ratio",
            ]
            rows = []
            for engine in engines:
                ratios = [ref / v for v, ref in zip(medians[engine], reference, strict=True)]
                is_ref = engine == "rdflib Graph"
                rows.append(
                    [
                        engine,
                        *[f"{v:,.1f}" for v in medians[engine]],
                        f"{statistics.median(medians[engine]):,.1f}",
                        f"{statistics.median(tails[engine]):,.1f}",
                        "(reference)" if is_ref else " ".join(fmt_ratio(r) for r in ratios),
                        "" if is_ref else fmt_ratio(statistics.median(ratios)),
                    ]
                )
            print()
            print(
                f"{QUERY_TITLES[name]}: latency in microseconds, {lookups} random bound "
                f"?{QUERY_SPECS[name]} per round, {rows_returned} rows in all (lower is better)"
            )
            print_table(header, rows)
        del memory, disk
        gc.collect()


QUERY_SPECS = {"point_lookup": "primitive", "scene_join": "scene"}  # query -> bound variable
QUERY_TITLES = {
    "point_lookup": "Point lookup (centreX of one primitive)",
    "scene_join": "3-pattern join (spheres of one scene with radius)",
}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0] if __doc__ else None)
    parser.add_argument("--scenes", type=int, default=2000, help="scenes to generate (2000)")
    parser.add_argument("--repeats", type=int, default=3, help="rounds per measurement (3)")
    parser.add_argument("--lookups", type=int, default=200, help="queries per round (200)")
    parser.add_argument("--tmpdir", default=None, help="where the on-disk stores go")
    args = parser.parse_args()
    if args.scenes < 1 or args.repeats < 1 or args.lookups < 1:
        parser.error("--scenes, --repeats and --lookups must be at least 1")

    began = time.perf_counter()
    raw = make_scenes(args.scenes, SEED)
    ox_scenes, rdf_scenes = to_engram(raw), to_rdflib(raw)
    quads = sum(len(scene) for scene in raw)
    tmp_root = args.tmpdir or tempfile.gettempdir()

    print("Engram store vs rdflib in-memory Graph (bench/store.py)")
    print(
        f"python {platform.python_version()}, pyoxigraph {pyoxigraph.__version__}, "
        f"rdflib {rdflib.__version__}, {os.cpu_count()} CPUs, "
        f"load average {os.getloadavg()[0]:.2f}"
    )
    print(
        f"data: {args.scenes:,} scenes, {quads:,} quads in the episodic graph "
        f"({quads / args.scenes:.1f} per scene), seed {SEED}"
    )
    print(
        f"{args.repeats} rounds, engines interleaved round-robin; on-disk stores under "
        f"{tmp_root} ({filesystem_of(tmp_root)})"
    )
    print("term construction (pyoxigraph and rdflib terms) is excluded from every timing")
    print()
    bench_inserts(ox_scenes, rdf_scenes, quads, args.repeats, args.tmpdir)
    bench_queries(raw, ox_scenes, rdf_scenes, args.lookups, args.repeats, args.tmpdir)
    print()
    print(f"total wall time {time.perf_counter() - began:.1f} s")


if __name__ == "__main__":
    main()
