"""prp-key: individuals of a class with an ``owl:hasKey`` that share every key value are the same.

``C owl:hasKey (p1 … pn)``, ``x`` and ``y`` both in ``C``, and for each ``pi`` one value ``zi``
with ``x pi zi`` and ``y pi zi``: then ``x owl:sameAs y``. The rule runs as an engine fact hook,
like the SWRL rules: each processed type or key-property fact is joined with the facts known so
far, so it fires when the last of its premises appears.

>>> from reasoners.owl_rl.engine import Engine
>>> from reasoners.owl_rl._terms import FIRST, NIL, REST
>>> e = Engine()
>>> e.add_all([("<Robot>", HAS_KEY, "_:l"), ("_:l", FIRST, "<serial>"), ("_:l", REST, NIL),
...            ("<r1>", TYPE, "<Robot>"), ("<r2>", TYPE, "<Robot>"),
...            ("<r1>", "<serial>", '"A7"'), ("<r2>", "<serial>", '"A7"')])
>>> add_key_rules(e)
>>> e.run()
>>> ("<r1>", SAME_AS, "<r2>") in e
True
"""

from reasoners.owl_rl._terms import HAS_KEY, SAME_AS, TYPE
from reasoners.owl_rl.engine import Engine

__all__ = ["KeyRunner", "add_key_rules"]

Key = tuple[str, tuple[str, ...]]


def add_key_rules(engine: Engine) -> None:
    """Attach the engine's ``owl:hasKey`` axioms (if any) as a fact hook; call it before the
    engine's first run."""
    keys = [
        (c, tuple(engine.list_items(head)))
        for c, heads in engine.sp.get(HAS_KEY, {}).items()
        for head in heads
    ]
    keys = [(c, properties) for c, properties in keys if properties]
    if keys:
        engine.fact_hooks.append(KeyRunner(keys))


class KeyRunner:
    """Runs prp-key as an engine fact hook."""

    def __init__(self, keys: list[Key]) -> None:
        self.by_class: dict[str, list[Key]] = {}
        self.by_property: dict[str, list[Key]] = {}
        for key in keys:
            self.by_class.setdefault(key[0], []).append(key)
            for p in set(key[1]):
                self.by_property.setdefault(p, []).append(key)

    def __call__(self, engine: Engine, s: str, p: str, o: str) -> None:
        if p == TYPE:
            for key in self.by_class.get(o, ()):
                _match(engine, s, key)
        for key in self.by_property.get(p, ()):
            if key[0] in engine.objects(s, TYPE):
                _match(engine, s, key)


def _match(engine: Engine, x: str, key: Key) -> None:
    cls, properties = key
    first, rest = properties[0], properties[1:]
    candidates = {y for z in engine.objects(x, first) for y in engine.subjects(first, z)}
    for y in candidates:
        if y == x or cls not in engine.objects(y, TYPE):
            continue
        if all(engine.objects(x, p) & engine.objects(y, p) for p in rest):
            engine.add(x, SAME_AS, y)
            engine.add(y, SAME_AS, x)
