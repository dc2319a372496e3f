"""Synthetic scene ontologies for benchmarks and tests of the OWL 2 RL reasoner.

A T-Box of geometric primitives, furniture and scenes (subclass chains up to five deep, defined
classes with existential, data-range, value and intersection restrictions, inverse, symmetric and
transitive object properties, data properties with domains) and an A-Box of scenes, each holding
four to eight objects with types, scores, levels, labels and spatial relations. The scenes are
independent, so the closure grows linearly with the number of scenes, like the one measured in
``reference/stack-measurements.md`` (section 2d) which this generator follows.

>>> lines = scene_ontology(1_000, seed=1)
>>> 900 < len(lines) < 1_100
True
>>> lines[0].endswith(" .")
True
"""

import random

from ontologies.vocab import OWL_NS, RDF_NS, RDFS_NS, XSD_NS

__all__ = ["EX", "scene_ontology", "tbox_lines"]

EX = "http://example.org/scene#"

_SUBCLASSES = [
    ("PhysicalObject", "Entity"),
    ("Primitive", "PhysicalObject"),
    ("Box", "Primitive"),
    ("Cube", "Box"),
    ("RoundPrimitive", "Primitive"),
    ("Sphere", "RoundPrimitive"),
    ("Cylinder", "RoundPrimitive"),
    ("Cone", "RoundPrimitive"),
    ("Container", "PhysicalObject"),
    ("Graspable", "PhysicalObject"),
    ("Mug", "Container"),
    ("Mug", "Graspable"),
    ("Bottle", "Container"),
    ("Bottle", "Graspable"),
    ("Furniture", "PhysicalObject"),
    ("Table", "Furniture"),
    ("Shelf", "Furniture"),
    ("Scene", "Entity"),
    ("IndoorScene", "Scene"),
    ("KitchenScene", "IndoorScene"),
    ("TabletopScene", "IndoorScene"),
]
_LEAVES = ["Cube", "Sphere", "Cylinder", "Cone", "Mug", "Bottle", "Table", "Shelf"]
_SCENE_KINDS = ["KitchenScene", "TabletopScene", "IndoorScene"]
_OBJECT_PROPERTIES = [
    "leftOf",
    "rightOf",
    "above",
    "below",
    "onTopOf",
    "near",
    "touches",
    "partOf",
    "hasPart",
    "inScene",
    "hasObject",
]
_DATA_PROPERTIES = ["score", "level", "timestamp"]


def _iri(name: str) -> str:
    return f"<{EX}{name}>"


def _t(s: str, p: str, o: str) -> str:
    return f"{s} {p} {o} ."


def tbox_lines() -> list[str]:
    """The T-Box as N-Triples lines (restrictions and lists use ``_:`` blank nodes)."""
    a, sco = f"<{RDF_NS}type>", f"<{RDFS_NS}subClassOf>"
    lines = [_t(f"<{EX}ontology>", a, f"<{OWL_NS}Ontology>")]
    classes = {c for pair in _SUBCLASSES for c in pair}
    classes |= {"StackedObject", "SupportingObject", "SceneWithContainer"}
    classes |= {"ObjectNearRound", "PartOfFurniture", "ScoredObject", "GroundObject"}
    lines += [_t(_iri(c), a, f"<{OWL_NS}Class>") for c in sorted(classes)]
    lines += [_t(_iri(c), sco, _iri(d)) for c, d in _SUBCLASSES]
    lines += [_t(_iri(p), a, f"<{OWL_NS}ObjectProperty>") for p in _OBJECT_PROPERTIES]
    lines += [_t(_iri(p), a, f"<{OWL_NS}DatatypeProperty>") for p in _DATA_PROPERTIES]
    inverse = f"<{OWL_NS}inverseOf>"
    lines += [
        _t(_iri("rightOf"), inverse, _iri("leftOf")),
        _t(_iri("below"), inverse, _iri("above")),
        _t(_iri("hasPart"), inverse, _iri("partOf")),
        _t(_iri("hasObject"), inverse, _iri("inScene")),
        _t(_iri("onTopOf"), f"<{RDFS_NS}subPropertyOf>", _iri("above")),
        _t(_iri("inScene"), f"<{RDFS_NS}domain>", _iri("PhysicalObject")),
        _t(_iri("inScene"), f"<{RDFS_NS}range>", _iri("Scene")),
        _t(_iri("score"), f"<{RDFS_NS}domain>", _iri("PhysicalObject")),
        _t(_iri("Sphere"), f"<{OWL_NS}disjointWith>", _iri("Cube")),
        _t(_iri("Scene"), f"<{OWL_NS}disjointWith>", _iri("PhysicalObject")),
    ]
    for p in ("leftOf", "above", "partOf"):
        lines.append(_t(_iri(p), a, f"<{OWL_NS}TransitiveProperty>"))
    for p in ("near", "touches"):
        lines.append(_t(_iri(p), a, f"<{OWL_NS}SymmetricProperty>"))
    # Defined classes: name = intersection of parts, each part a class or a restriction.
    defined: list[tuple[str, list[str | tuple[str, str, str]]]] = [
        ("StackedObject", ["PhysicalObject", ("some", "above", _iri("PhysicalObject"))]),
        ("SupportingObject", [("some", "below", _iri("PhysicalObject"))]),
        ("SceneWithContainer", ["Scene", ("some", "hasObject", _iri("Container"))]),
        ("ObjectNearRound", [("some", "near", _iri("RoundPrimitive"))]),
        ("PartOfFurniture", [("some", "partOf", _iri("Furniture"))]),
        ("ScoredObject", ["PhysicalObject", ("some", "score", f"<{XSD_NS}double>")]),
        ("GroundObject", [("value", "level", f'"0"^^<{XSD_NS}integer>')]),
    ]
    for n, (name, parts) in enumerate(defined):
        nodes: list[str] = []
        for k, part in enumerate(parts):
            if isinstance(part, str):
                nodes.append(_iri(part))
                continue
            kind, prop, filler = part
            r = f"_:r{n}x{k}"
            nodes.append(r)
            lines.append(_t(r, a, f"<{OWL_NS}Restriction>"))
            lines.append(_t(r, f"<{OWL_NS}onProperty>", _iri(prop)))
            key = "someValuesFrom" if kind == "some" else "hasValue"
            lines.append(_t(r, f"<{OWL_NS}{key}>", filler))
        if len(nodes) == 1:
            lines.append(_t(_iri(name), f"<{OWL_NS}equivalentClass>", nodes[0]))
            continue
        head = f"_:l{n}x0"
        lines.append(_t(f"_:i{n}", a, f"<{OWL_NS}Class>"))
        lines.append(_t(f"_:i{n}", f"<{OWL_NS}intersectionOf>", head))
        lines.append(_t(_iri(name), f"<{OWL_NS}equivalentClass>", f"_:i{n}"))
        for k, node in enumerate(nodes):
            rest = f"_:l{n}x{k + 1}" if k + 1 < len(nodes) else f"<{RDF_NS}nil>"
            lines.append(_t(f"_:l{n}x{k}", f"<{RDF_NS}first>", node))
            lines.append(_t(f"_:l{n}x{k}", f"<{RDF_NS}rest>", rest))
    lines.append(
        _t(_iri("Scene"), sco, "_:avf"),
    )
    lines += [
        _t("_:avf", a, f"<{OWL_NS}Restriction>"),
        _t("_:avf", f"<{OWL_NS}onProperty>", _iri("hasObject")),
        _t("_:avf", f"<{OWL_NS}allValuesFrom>", _iri("PhysicalObject")),
    ]
    return lines


def scene_ontology(triples: int, *, seed: int = 0) -> list[str]:
    """About ``triples`` N-Triples lines: the T-Box, then scenes until the count is reached.

    The same ``seed`` gives the same lines. Transitive relations are acyclic within a scene.
    """
    rng = random.Random(seed)
    a = f"<{RDF_NS}type>"
    lines = tbox_lines()
    scene = 0
    while len(lines) < triples:
        s = _iri(f"scene{scene}")
        lines.append(_t(s, a, _iri(rng.choice(_SCENE_KINDS))))
        lines.append(_t(s, _iri("level"), f'"{rng.randint(0, 3)}"^^<{XSD_NS}integer>'))
        lines.append(_t(s, _iri("timestamp"), f'"{1_700_000_000 + scene}"^^<{XSD_NS}integer>'))
        objects = [_iri(f"scene{scene}_obj{k}") for k in range(rng.randint(4, 8))]
        for obj in objects:
            lines.append(_t(obj, a, _iri(rng.choice(_LEAVES))))
            lines.append(_t(obj, _iri("inScene"), s))
            lines.append(_t(obj, _iri("score"), f'"{rng.randint(1, 99) / 100}"^^<{XSD_NS}double>'))
            lines.append(_t(obj, _iri("level"), f'"{rng.randint(0, 2)}"^^<{XSD_NS}integer>'))
            lines.append(_t(obj, f"<{RDFS_NS}label>", f'"object {obj[-6:-1]}"'))
        for _ in range(rng.randint(5, 10)):
            i, j = sorted(rng.sample(range(len(objects)), 2))
            prop = rng.choice(["leftOf", "above", "onTopOf", "near", "touches", "partOf"])
            lines.append(_t(objects[i], _iri(prop), objects[j]))
        scene += 1
    return lines
