"""DL-safe SWRL rules found in an ontology, with the common ``swrlb`` built-ins.

Rules are read from their RDF form (``swrl:Imp`` with ``swrl:body`` and ``swrl:head`` atom
lists), which is what Protégé writes in RDF/XML and Turtle. Variables are the terms typed
``swrl:Variable``. Rules are DL-safe: a variable only ever binds to a term that occurs in a fact,
so rules never invent individuals; a built-in such as ``swrlb:add`` may bind its first argument
to a new literal.

A rule runs inside the engine's semi-naive loop: every processed fact that matches a body atom
is joined with the rest of the body against the facts known so far, and the head is added.

Supported atoms: class, individual-property, datavalued-property, same-individual,
different-individuals, data-range and built-in atoms. ``sameAs(?x, ?y)`` holds for every term and
itself; ``differentFrom(?x, ?y)`` holds both ways for an ``owl:differentFrom`` in either direction
and for every two members of an ``owl:AllDifferent``. Built-ins: ``equal``, ``notEqual``,
``lessThan``, ``lessThanOrEqual``, ``greaterThan``, ``greaterThanOrEqual``, ``add``,
``subtract``, ``multiply``, ``divide``, ``integerDivide``, ``mod``, ``pow``, ``unaryPlus``,
``unaryMinus``, ``abs``, ``ceiling``, ``floor``, ``round``, ``stringConcat``, ``stringLength``,
``contains``, ``startsWith``, ``endsWith``. Anything else is refused with
:class:`~reasoners.owl_rl.errors.SwrlRuleError`.

>>> str(Atom("class", "<C>", ("?x",)))
'<C>(?x)'
"""

import math
import re
from collections.abc import Callable
from dataclasses import dataclass
from decimal import Decimal, InvalidOperation

from pyoxigraph import Literal, NamedNode

from ontologies.vocab import SWRLB_NS, XSD_NS
from reasoners.owl_rl._terms import (
    ALL_DIFFERENT,
    DIFFERENT_FROM,
    DISTINCT_MEMBERS,
    MEMBERS,
    SAME_AS,
    TYPE,
    literal_datatype,
    swrl,
    unescape,
)
from reasoners.owl_rl.engine import Engine
from reasoners.owl_rl.errors import SwrlRuleError

__all__ = ["Atom", "Rule", "SwrlRunner", "parse_rules"]

IMP = swrl("Imp")
VARIABLE = swrl("Variable")
_Value = int | float | Decimal | str | bool


@dataclass(frozen=True)
class Atom:
    """One atom: ``kind`` is class, property, same, different, datarange or builtin."""

    kind: str
    predicate: str
    args: tuple[str, ...]

    def __str__(self) -> str:
        return f"{self.predicate}({', '.join(self.args)})"


@dataclass(frozen=True)
class Rule:
    """A rule ``body -> head``; variables are written ``?name``."""

    iri: str
    body: tuple[Atom, ...]
    head: tuple[Atom, ...]


def parse_rules(engine: Engine) -> list[Rule]:
    """Every ``swrl:Imp`` among the engine's facts, checked and compiled.

    Raises :class:`SwrlRuleError` naming the rule, the atom and what was expected when a rule
    is malformed, uses an unknown built-in, or is not DL-safe (a head variable unbound by the
    body).
    """
    variables = {v for v in engine.subjects(TYPE, VARIABLE)}
    rules = []
    for imp in sorted(engine.subjects(TYPE, IMP)):
        body = _atoms(engine, imp, "body", variables)
        head = _atoms(engine, imp, "head", variables)
        bound = {a for atom in body for a in atom.args if a.startswith("?")}
        for atom in head:
            free = [a for a in atom.args if a.startswith("?") and a not in bound]
            if free or atom.kind == "builtin":
                raise SwrlRuleError(
                    f"SWRL rule {imp}: head atom {atom} uses {', '.join(free) or 'a built-in'}; "
                    "expected only variables bound by the body (DL-safe rules)"
                )
        rules.append(Rule(imp, body, head))
    return rules


def _atoms(engine: Engine, imp: str, part: str, variables: set[str]) -> tuple[Atom, ...]:
    heads = engine.objects(imp, swrl(part))
    if len(heads) != 1:
        raise SwrlRuleError(f"SWRL rule {imp}: swrl:{part} has {len(heads)} values, expected 1")
    atoms = []
    for node in engine.list_items(next(iter(heads))):
        atoms.append(_atom(engine, imp, node, variables))
    return tuple(atoms)


def _one(engine: Engine, imp: str, node: str, name: str) -> str:
    values = engine.objects(node, swrl(name))
    if len(values) != 1:
        raise SwrlRuleError(
            f"SWRL rule {imp}: atom {node} has {len(values)} swrl:{name} values, expected 1"
        )
    return next(iter(values))


def _var(term: str, variables: set[str]) -> str:
    if term in variables:
        local = re.split(r"[#/:]", term[1:-1])[-1]
        return f"?{local}|{term}"
    return term


def _atom(engine: Engine, imp: str, node: str, variables: set[str]) -> Atom:
    kinds = engine.objects(node, TYPE)

    def arg(name: str) -> str:
        return _var(_one(engine, imp, node, name), variables)

    if swrl("ClassAtom") in kinds:
        return Atom("class", _one(engine, imp, node, "classPredicate"), (arg("argument1"),))
    if swrl("IndividualPropertyAtom") in kinds or swrl("DatavaluedPropertyAtom") in kinds:
        predicate = _one(engine, imp, node, "propertyPredicate")
        return Atom("property", predicate, (arg("argument1"), arg("argument2")))
    if swrl("SameIndividualAtom") in kinds:
        return Atom("same", SAME_AS, (arg("argument1"), arg("argument2")))
    if swrl("DifferentIndividualsAtom") in kinds:
        return Atom("different", DIFFERENT_FROM, (arg("argument1"), arg("argument2")))
    if swrl("DataRangeAtom") in kinds:
        return Atom("datarange", _one(engine, imp, node, "dataRange"), (arg("argument1"),))
    if swrl("BuiltinAtom") in kinds:
        builtin = _one(engine, imp, node, "builtin")
        name = builtin[1 + len(SWRLB_NS) : -1] if builtin.startswith(f"<{SWRLB_NS}") else ""
        if name not in BUILTINS:
            raise SwrlRuleError(
                f"SWRL rule {imp}: built-in {builtin} is not supported; expected one of "
                f"swrlb:{', swrlb:'.join(sorted(BUILTINS))}"
            )
        args = engine.list_items(_one(engine, imp, node, "arguments"))
        return Atom("builtin", name, tuple(_var(a, variables) for a in args))
    raise SwrlRuleError(
        f"SWRL rule {imp}: atom {node} has types {sorted(kinds)}; expected a swrl:ClassAtom, "
        "IndividualPropertyAtom, DatavaluedPropertyAtom, SameIndividualAtom, "
        "DifferentIndividualsAtom, DataRangeAtom or BuiltinAtom"
    )


# Built-ins ------------------------------------------------------------------------------------

_INTEGER_NAMES = (
    "integer int long short byte nonNegativeInteger positiveInteger nonPositiveInteger "
    "negativeInteger unsignedLong unsignedInt unsignedShort unsignedByte"
)
_INTEGER_TYPES = {f"<{XSD_NS}{name}>" for name in _INTEGER_NAMES.split()}


def value_of(term: str) -> _Value | None:
    """The Python value of a literal term (int, Decimal, float, bool or str), None for IRIs."""
    if not term.startswith('"'):
        return None
    end = term.rfind('"')
    lexical = term[1:end]
    if "\\" in lexical:
        lexical = unescape(lexical)
    datatype = literal_datatype(term)
    try:
        if datatype in _INTEGER_TYPES:
            return int(lexical)
        if datatype == f"<{XSD_NS}decimal>":
            return Decimal(lexical)
        if datatype in (f"<{XSD_NS}double>", f"<{XSD_NS}float>"):
            return float(lexical.replace("INF", "inf"))
        if datatype == f"<{XSD_NS}boolean>":
            return lexical in ("true", "1")
    except (ValueError, InvalidOperation):
        return None
    return lexical


def term_of(value: _Value) -> str:
    """The canonical literal term for a value, as the store writes it."""
    if isinstance(value, bool):
        literal = Literal("true" if value else "false", datatype=NamedNode(XSD_NS + "boolean"))
    elif isinstance(value, int):
        literal = Literal(str(value), datatype=NamedNode(XSD_NS + "integer"))
    elif isinstance(value, Decimal):
        text = format(value.normalize(), "f")
        literal = Literal(text, datatype=NamedNode(XSD_NS + "decimal"))
    elif isinstance(value, float):
        if value.is_integer() and abs(value) < 1e16:
            text = str(int(value))
        elif math.isfinite(value):
            text = format(Decimal(repr(value)), "f")
        else:
            text = "NaN" if math.isnan(value) else ("INF" if value > 0 else "-INF")
        literal = Literal(text, datatype=NamedNode(XSD_NS + "double"))
    else:
        literal = Literal(value)
    return str(literal)


def _number(value: _Value | None) -> int | float | Decimal | None:
    if isinstance(value, bool) or not isinstance(value, int | float | Decimal):
        return None
    return value


def _arith(op: Callable[..., int | float | Decimal]) -> Callable[[list[_Value]], _Value | None]:
    def apply(values: list[_Value]) -> _Value | None:
        numbers = [_number(v) for v in values]
        if any(n is None for n in numbers):
            return None
        if any(isinstance(n, float) for n in numbers):
            numbers = [float(n) for n in numbers if n is not None]
        elif any(isinstance(n, Decimal) for n in numbers):
            numbers = [Decimal(n) for n in numbers if n is not None]
        try:
            return op(*numbers)
        except (ArithmeticError, ValueError, TypeError):
            return None

    return apply


def _divide(a: float | Decimal | int, b: float | Decimal | int) -> float | Decimal:
    if isinstance(a, float) or isinstance(b, float):
        return float(a) / float(b)
    return Decimal(a) / Decimal(b)


def _compare(test: Callable[[object, object], bool]) -> Callable[[_Value, _Value], bool]:
    def apply(a: _Value, b: _Value) -> bool:
        na, nb = _number(a), _number(b)
        if na is not None and nb is not None:
            return test(float(na) if isinstance(na, float) else Decimal(na), _as(na, nb))
        try:
            return test(a, b)
        except TypeError:
            return False

    return apply


def _as(reference: object, value: int | float | Decimal) -> float | Decimal:
    return float(value) if isinstance(reference, float) else Decimal(value)


COMPARISONS: dict[str, Callable[[_Value, _Value], bool]] = {
    "equal": _compare(lambda a, b: a == b),
    "notEqual": _compare(lambda a, b: a != b),
    "lessThan": _compare(lambda a, b: a < b),  # type: ignore[operator]
    "lessThanOrEqual": _compare(lambda a, b: a <= b),  # type: ignore[operator]
    "greaterThan": _compare(lambda a, b: a > b),  # type: ignore[operator]
    "greaterThanOrEqual": _compare(lambda a, b: a >= b),  # type: ignore[operator]
    "contains": lambda a, b: isinstance(a, str) and isinstance(b, str) and b in a,
    "startsWith": lambda a, b: isinstance(a, str) and isinstance(b, str) and a.startswith(b),
    "endsWith": lambda a, b: isinstance(a, str) and isinstance(b, str) and a.endswith(b),
}
FUNCTIONS: dict[str, Callable[[list[_Value]], _Value | None]] = {
    "add": _arith(lambda *n: sum(n[1:], n[0])),
    "subtract": _arith(lambda a, b: a - b),
    "multiply": _arith(lambda *n: math.prod(n[1:], start=n[0])),
    "divide": _arith(_divide),
    "integerDivide": _arith(lambda a, b: int(a / b) if b else 1 // 0),
    "mod": _arith(lambda a, b: math.fmod(a, b) if isinstance(a, float) else a % b),
    "pow": _arith(lambda a, b: a**b),
    "unaryPlus": _arith(lambda a: a),
    "unaryMinus": _arith(lambda a: -a),
    "abs": _arith(abs),
    "ceiling": _arith(lambda a: math.ceil(a) if not isinstance(a, float) else float(math.ceil(a))),
    "floor": _arith(lambda a: math.floor(a) if not isinstance(a, float) else float(math.floor(a))),
    "round": _arith(lambda a: math.floor(a + (Decimal("0.5") if isinstance(a, Decimal) else 0.5))),
    "stringConcat": lambda values: "".join(str(v) for v in values),
    "stringLength": lambda values: len(values[0]) if isinstance(values[0], str) else None,
}
BUILTINS = set(COMPARISONS) | set(FUNCTIONS)


def _builtin(atom: Atom, binding: dict[str, str]) -> list[dict[str, str]] | None:
    """Solutions of a built-in under ``binding``; None if it cannot run yet (inputs unbound)."""
    args = [binding.get(a, a) if a.startswith("?") else a for a in atom.args]
    if atom.predicate in COMPARISONS:
        if any(a.startswith("?") for a in args):
            return None
        a, b = (value_of(x) for x in args[:2])
        if a is None or b is None:
            ok = COMPARISONS[atom.predicate](args[0], args[1])  # IRIs compare as terms
        else:
            ok = COMPARISONS[atom.predicate](a, b)
        return [binding] if ok else []
    if any(a.startswith("?") for a in args[1:]):
        return None
    values = [value_of(x) for x in args[1:]]
    if any(v is None for v in values):
        return []
    result = FUNCTIONS[atom.predicate]([v for v in values if v is not None])
    if result is None:
        return []
    term = term_of(result)
    first = args[0]
    if first.startswith("?"):
        return [{**binding, first: term}]
    expected = value_of(first)
    equal = COMPARISONS["equal"]
    return [binding] if expected is not None and equal(expected, value_of(term) or "") else []


# Evaluation -----------------------------------------------------------------------------------


class SwrlRunner:
    """Runs compiled rules as an engine fact hook (semi-naive: one body atom is the new fact)."""

    def __init__(self, rules: list[Rule]) -> None:
        self.rules = rules
        self._by_predicate: dict[str, list[tuple[Rule, int]]] = {}
        self._by_class: dict[str, list[tuple[Rule, int]]] = {}
        for rule in rules:
            for i, atom in enumerate(rule.body):
                if atom.kind in ("class", "datarange"):
                    self._by_class.setdefault(atom.predicate, []).append((rule, i))
                elif atom.kind != "builtin":
                    self._by_predicate.setdefault(atom.predicate, []).append((rule, i))

    def __call__(self, engine: Engine, s: str, p: str, o: str) -> None:
        triggered = self._by_class.get(o, []) if p == TYPE else []
        triggered = triggered + self._by_predicate.get(p, [])
        for rule, index in triggered:
            atom = rule.body[index]
            if atom.kind in ("class", "datarange"):
                self._complete(engine, rule, index, (s,))
            elif atom.kind == "different":  # differentFrom is symmetric
                self._complete(engine, rule, index, (s, o))
                self._complete(engine, rule, index, (o, s))
            else:
                self._complete(engine, rule, index, (s, o))
        if self._by_predicate.get(DIFFERENT_FROM) and _declares_all_different(engine, s, p, o):
            for x, y in _all_different_pairs(engine, s):
                for rule, index in self._by_predicate[DIFFERENT_FROM]:
                    self._complete(engine, rule, index, (x, y))

    def _complete(self, engine: Engine, rule: Rule, index: int, terms: tuple[str, ...]) -> None:
        """Fire ``rule`` for every solution where body atom ``index`` matches ``terms``."""
        binding: dict[str, str] = {}
        pairs = zip(rule.body[index].args, terms, strict=True)
        if not all(_unify(arg, term, binding) for arg, term in pairs):
            return
        rest = [a for i, a in enumerate(rule.body) if i != index]
        for solution in _join(engine, rest, binding):
            for head in rule.head:
                _fire(engine, head, solution)


def _declares_all_different(engine: Engine, s: str, p: str, o: str) -> bool:
    """Is the fact the last piece of an ``owl:AllDifferent`` axiom (its type or its list)?"""
    if p == TYPE and o == ALL_DIFFERENT:
        return True
    return p in (MEMBERS, DISTINCT_MEMBERS) and ALL_DIFFERENT in engine.objects(s, TYPE)


def _all_different_pairs(engine: Engine, axiom: str) -> set[tuple[str, str]]:
    """Every ordered pair of distinct members of one ``owl:AllDifferent`` axiom."""
    pairs: set[tuple[str, str]] = set()
    for list_predicate in (MEMBERS, DISTINCT_MEMBERS):
        for head in engine.objects(axiom, list_predicate):
            positions = engine.list_positions(head)
            for i, xs in enumerate(positions):
                for j, ys in enumerate(positions):
                    if i != j:
                        pairs.update((x, y) for x in xs for y in ys if x != y)
    return pairs


def different_from(engine: Engine, x: str) -> set[str]:
    """The terms stated different from ``x``: ``owl:differentFrom`` in either direction, and the
    other members of every ``owl:AllDifferent`` that lists ``x`` (SWRL's DifferentIndividuals
    atom holds for all of them)."""
    found = set(engine.objects(x, DIFFERENT_FROM)) | engine.subjects(DIFFERENT_FROM, x)
    for axiom in engine.subjects(TYPE, ALL_DIFFERENT):
        found.update(y for a, y in _all_different_pairs(engine, axiom) if a == x)
    return found


def _stated_different_pairs(engine: Engine) -> set[tuple[str, str]]:
    pairs: set[tuple[str, str]] = set()
    for s, objects in engine.sp.get(DIFFERENT_FROM, {}).items():
        for o in objects:
            pairs.update(((s, o), (o, s)))
    for axiom in engine.subjects(TYPE, ALL_DIFFERENT):
        pairs |= _all_different_pairs(engine, axiom)
    return pairs


def _unify(arg: str, term: str, binding: dict[str, str]) -> bool:
    if not arg.startswith("?"):
        return arg == term
    bound = binding.get(arg)
    if bound is None:
        binding[arg] = term
        return True
    return bound == term


def _join(engine: Engine, atoms: list[Atom], binding: dict[str, str]) -> list[dict[str, str]]:
    if not atoms:
        return [binding]
    # Pick the next atom: a built-in that can run, else the atom with the most bound arguments.
    best, best_score = 0, -1
    for i, atom in enumerate(atoms):
        bound = sum(1 for a in atom.args if not a.startswith("?") or a in binding)
        if atom.kind == "builtin":
            if _builtin(atom, binding) is not None:
                best, best_score = i, 99
                break
            continue
        if bound > best_score:
            best, best_score = i, bound
    atom, rest = atoms[best], atoms[:best] + atoms[best + 1 :]
    if atom.kind == "builtin":
        solutions = _builtin(atom, binding)
        if solutions is None:  # no built-in can run and nothing else is left: unsafe, no match
            return []
        return [r for b in solutions for r in _join(engine, rest, b)]
    results = []
    for candidate in _candidates(engine, atom, binding):
        results += _join(engine, rest, candidate)
    return results


def _candidates(engine: Engine, atom: Atom, binding: dict[str, str]) -> list[dict[str, str]]:
    args = [binding.get(a, a) for a in atom.args]
    if atom.kind in ("class", "datarange"):
        x = args[0]
        if x.startswith("?"):
            return [{**binding, x: m} for m in engine.subjects(TYPE, atom.predicate)]
        return [binding] if atom.predicate in engine.objects(x, TYPE) else []
    p = atom.predicate
    x, y = args
    pairs: list[tuple[str, str]]
    if atom.kind == "different":
        if not x.startswith("?"):
            pairs = [(x, o) for o in different_from(engine, x)]
        elif not y.startswith("?"):
            pairs = [(s, y) for s in different_from(engine, y)]
        else:
            pairs = sorted(_stated_different_pairs(engine))
    elif not x.startswith("?"):
        objects = set(engine.objects(x, p))
        if atom.kind == "same":  # x owl:sameAs x holds for every x (eq-ref)
            objects.add(x)
        pairs = [(x, o) for o in objects]
    elif not y.startswith("?"):
        subjects = set(engine.subjects(p, y))
        if atom.kind == "same":
            subjects.add(y)
        pairs = [(s, y) for s in subjects]
    else:
        pairs = [(s, o) for s, objects in engine.sp.get(p, {}).items() for o in objects]
        if atom.kind == "same":
            pairs += [(s, s) for s in _individuals(engine)]
    results = []
    for s, o in pairs:
        candidate = dict(binding)
        if _unify(x, s, candidate) and _unify(y, o, candidate):
            results.append(candidate)
    return results


def _individuals(engine: Engine) -> set[str]:
    """The terms typed by some class, literals excluded (what a DL-safe variable binds to)."""
    return {x for x in engine.sp.get(TYPE, {}) if x[0] != '"'}


def _fire(engine: Engine, atom: Atom, binding: dict[str, str]) -> None:
    args = [binding.get(a, a) for a in atom.args]
    if atom.kind in ("class", "datarange"):
        engine.add(args[0], TYPE, atom.predicate)
    elif atom.kind == "same":
        if args[0] != args[1]:
            engine.add(args[0], SAME_AS, args[1])
    else:
        engine.add(args[0], atom.predicate, args[1])
