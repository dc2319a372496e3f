"""The OWL 2 RL rules, evaluated semi-naively over indexed triples in memory.

Every fact is a ``(subject, predicate, object)`` tuple of N-Triples terms, indexed by predicate
twice (subject to objects, object to subjects). A fact enters the indexes once, when it is first
derived, and is then processed once: every rule instance whose body holds the fact is completed
by index look-ups against everything known so far. Whichever body fact of an instance is processed
last finds the others, so each instance fires exactly when its last premise appears; that is
semi-naive evaluation, and it is what makes a second run after a few new facts cheap.

Schema facts (T-Box: sub-classes, restrictions, lists, property characteristics) are processed
before instance facts. What a rule needs from the schema about one predicate or one class is
cached (:mod:`reasoners.owl_rl.schema`) and the caches are dropped when the schema
grows. When the schema grows after instance facts were processed (an incremental run that adds
an axiom), the instance facts that could join with the new axiom are processed again; processing
is idempotent, so that only costs time.

Literal subjects (rule dt-type2: ``"1"^^xsd:integer rdf:type xsd:integer``) are kept as internal
facts so that data-range restrictions work; the caller leaves them out of what it writes.

>>> e = Engine()
>>> e.add_all([("<a>", TYPE, "<B>"), ("<B>", SUB_CLASS_OF, "<C>")])
>>> e.run()
>>> ("<a>", TYPE, "<C>") in e
True
"""

from collections.abc import Callable, Iterable, Iterator
from dataclasses import dataclass, field

from reasoners.owl_rl._terms import (
    ALL_VALUES_FROM,
    ANNOTATION_PROPERTIES,
    ANNOTATION_PROPERTY,
    ASYMMETRIC,
    CLASS,
    DATATYPE,
    DATATYPE_PROPERTY,
    DIFFERENT_FROM,
    DOMAIN,
    EQUIVALENT_CLASS,
    EQUIVALENT_PROPERTY,
    FIRST,
    FUNCTIONAL,
    HAS_VALUE,
    INTERSECTION_OF,
    INVERSE_FUNCTIONAL,
    INVERSE_OF,
    IRREFLEXIVE,
    MAX_CARDINALITY,
    MAX_QUALIFIED_CARDINALITY,
    NIL,
    NOTHING,
    OBJECT_PROPERTY,
    ON_CLASS,
    ON_PROPERTY,
    ONE_OF,
    PROPERTY,
    PROPERTY_CHAIN,
    RANGE,
    REST,
    SAME_AS,
    SOME_VALUES_FROM,
    SUB_CLASS_OF,
    SUB_PROPERTY_OF,
    SYMMETRIC,
    THING,
    TRANSITIVE,
    TYPE,
    UNION_OF,
    literal_datatype,
    swrl,
)
from reasoners.owl_rl.datatypes import RL_DATATYPES, value_key, value_types
from reasoners.owl_rl.schema import (
    ClassInfo,
    PropertyInfo,
    class_info,
    process_schema,
    property_info,
    schema_pass,
)

__all__ = ["AXIOMS", "Engine", "Fact"]

_DATA_RANGE = swrl("dataRange")

Fact = tuple[str, str, str]
_EMPTY: frozenset[str] = frozenset()
_Index = dict[str, dict[str, set[str]]]

SCHEMA_PREDICATES = frozenset(
    {
        SUB_CLASS_OF,
        EQUIVALENT_CLASS,
        SUB_PROPERTY_OF,
        EQUIVALENT_PROPERTY,
        INVERSE_OF,
        DOMAIN,
        RANGE,
        ON_PROPERTY,
        ON_CLASS,
        SOME_VALUES_FROM,
        ALL_VALUES_FROM,
        HAS_VALUE,
        MAX_CARDINALITY,
        MAX_QUALIFIED_CARDINALITY,
        INTERSECTION_OF,
        UNION_OF,
        ONE_OF,
        PROPERTY_CHAIN,
        FIRST,
        REST,
    }
)
SCHEMA_TYPES = frozenset(
    {
        CLASS,
        OBJECT_PROPERTY,
        DATATYPE_PROPERTY,
        PROPERTY,
        FUNCTIONAL,
        INVERSE_FUNCTIONAL,
        SYMMETRIC,
        TRANSITIVE,
        IRREFLEXIVE,
        ASYMMETRIC,
    }
)
AXIOMS: tuple[Fact, ...] = (
    (THING, TYPE, CLASS),  # cls-thing
    (NOTHING, TYPE, CLASS),  # cls-nothing1
    *((p, TYPE, ANNOTATION_PROPERTY) for p in ANNOTATION_PROPERTIES),  # prp-ap
    *((dt, TYPE, DATATYPE) for dt in sorted(RL_DATATYPES)),  # dt-type1
)
"""The body-less OWL 2 RL rules: facts that hold in every ontology."""


@dataclass
class Engine:
    """Facts, their indexes and the OWL 2 RL rules over them.

    ``add_all`` puts facts in; ``run`` derives their consequences; ``take_log`` lists what
    was recorded since its last call. Rule hooks (``fact_hooks``) let SWRL rules see each
    processed fact.
    """

    sp: _Index = field(default_factory=dict)
    op: _Index = field(default_factory=dict)
    fact_hooks: list[Callable[["Engine", str, str, str], None]] = field(default_factory=list)
    _schema_queue: list[Fact] = field(default_factory=list)
    queue: list[Fact] = field(default_factory=list)
    _log: list[Fact] = field(default_factory=list)
    _typed_literals: set[str] = field(default_factory=set)
    ill_typed: set[str] = field(default_factory=set)
    """Literals whose lexical form is not valid for their datatype (dt-not-type reports them)."""
    mistyped: set[tuple[str, str]] = field(default_factory=set)
    """(literal, datatype) type facts the datatype's value space does not hold (dt-not-type)."""
    unequal_same: set[tuple[str, str]] = field(default_factory=set)
    """Literals of different values found ``owl:sameAs`` (dt-diff), each pair sorted."""
    _datatypes_in_use: set[str] = field(default_factory=set)
    _literals_by_value: dict[object, set[str]] = field(default_factory=dict)
    _equated_literals: set[str] = field(default_factory=set)
    _schema_generation: int = 0
    _cached_generation: int = -1
    _passed_generation: int = -1
    property_cache: dict[str, PropertyInfo] = field(default_factory=dict)
    class_cache: dict[str, ClassInfo] = field(default_factory=dict)
    instances_processed: bool = False
    _quiet: bool = False  # may type facts skip the queue? (see _type)

    # Facts ------------------------------------------------------------------------------------

    def __contains__(self, fact: object) -> bool:
        if not isinstance(fact, tuple) or len(fact) != 3:
            return False
        s, p, o = fact
        return o in self.sp.get(p, {}).get(s, _EMPTY)

    def __len__(self) -> int:
        return sum(len(objects) for index in self.sp.values() for objects in index.values())

    def facts(self) -> Iterator[Fact]:
        """Every fact, literal subjects included."""
        for p, index in self.sp.items():
            for s, objects in index.items():
                for o in objects:
                    yield s, p, o

    def objects(self, s: str, p: str) -> set[str] | frozenset[str]:
        return self.sp.get(p, {}).get(s, _EMPTY)

    def subjects(self, p: str, o: str) -> set[str] | frozenset[str]:
        return self.op.get(p, {}).get(o, _EMPTY)

    def add(self, s: str, p: str, o: str) -> bool:
        """Record a fact and queue it for processing; False if it was known.

        ``x owl:sameAs x`` (eq-ref) holds for every term and is never recorded.
        """
        if s == o and p == SAME_AS:
            return False
        by_subject = self.sp.get(p)
        if by_subject is None:
            by_subject = self.sp[p] = {}
            self.op[p] = {}
        objects = by_subject.get(s)
        if objects is None:
            by_subject[s] = {o}
        elif o in objects:
            return False
        else:
            objects.add(o)
        by_object = self.op[p]
        subjects = by_object.get(o)
        if subjects is None:
            by_object[o] = {s}
        else:
            subjects.add(s)
        fact = (s, p, o)
        self._log.append(fact)
        if p in SCHEMA_PREDICATES or (p == TYPE and o in SCHEMA_TYPES):
            self._schema_generation += 1
            self._schema_queue.append(fact)
            if o in RL_DATATYPES and o not in self._datatypes_in_use:
                self._use_datatype(o)
        else:
            self.queue.append(fact)
            if p == TYPE and s[0] == '"' and o in RL_DATATYPES and o not in value_types(s):
                if s not in self.ill_typed:
                    self.mistyped.add((s, o))
            elif p == _DATA_RANGE and o in RL_DATATYPES and o not in self._datatypes_in_use:
                self._use_datatype(o)
        if o[0] == '"' and o not in self._typed_literals:
            self._type_literal(o)
        return True

    def add_all(self, facts: Iterable[Fact]) -> None:
        """Record facts (asserted ones, or the axioms) for the next :meth:`run`."""
        add = self.add
        for s, p, o in facts:
            add(s, p, o)

    def literals(self) -> set[str]:
        """The literals seen as objects (every literal subject is one of them)."""
        return self._typed_literals

    def take_log(self) -> list[Fact]:
        """The facts recorded since the last call, in order."""
        log, self._log = self._log, []
        return log

    def _type_literal(self, literal: str) -> None:
        """dt-type2 and dt-eq for a literal seen for the first time.

        The literal is typed with every datatype of the map that holds its value and that the
        schema mentions (only a rule that names a datatype can use such a fact, and literal
        subjects never leave the engine; :meth:`_use_datatype` types the literals already seen
        when the schema names a new one). An ill-typed literal is kept in :attr:`ill_typed`.
        A literal with the same value as one seen before is ``owl:sameAs`` it (dt-eq).
        """
        self._typed_literals.add(literal)
        types = value_types(literal)
        if not types:
            if literal_datatype(literal) in RL_DATATYPES:
                self.ill_typed.add(literal)
            return
        for datatype in types & self._datatypes_in_use:
            self.add(literal, TYPE, datatype)
        key = value_key(literal)
        same = self._literals_by_value.setdefault(key, set())
        for other in list(same):
            self.add(literal, SAME_AS, other)
        same.add(literal)

    def _equate_literal(self, literal: str) -> None:
        """A literal is the same as some term, so its types and its differences pass to that
        term (eq-rep): type it with every datatype of its value (dt-type2), and make it
        different from every other such literal of another value (dt-diff)."""
        self._equated_literals.add(literal)
        for datatype in value_types(literal):
            self.add(literal, TYPE, datatype)
        key = value_key(literal)
        if key is None:
            return
        for other in list(self._equated_literals):
            other_key = value_key(other)
            if other_key is not None and other_key != key:
                self.add(literal, DIFFERENT_FROM, other)
                self.add(other, DIFFERENT_FROM, literal)

    def _use_datatype(self, datatype: str) -> None:
        """The schema names ``datatype``: type the literals seen so far that belong to it."""
        self._datatypes_in_use.add(datatype)
        for literal in list(self._typed_literals):
            if datatype in value_types(literal):
                self.add(literal, TYPE, datatype)

    def untype_literals(self, literals: Iterable[str]) -> None:
        """Forget that ``literals`` were typed (their type facts were taken out): the next
        fact that uses one types it again."""
        literals = set(literals)
        self._typed_literals -= literals
        self._equated_literals -= literals
        self.ill_typed -= literals
        self.mistyped = {pair for pair in self.mistyped if pair[0] not in literals}
        self.unequal_same = {pair for pair in self.unequal_same if literals.isdisjoint(pair)}
        for literal in literals:
            self._literals_by_value.get(value_key(literal), set()).discard(literal)

    # Running ----------------------------------------------------------------------------------

    def run(self) -> None:
        """Derive every consequence of the facts recorded so far."""
        for _ in self.run_stepwise(None):
            pass

    def run_stepwise(self, every: int | None) -> Iterator[None]:
        """Derive every consequence, as :meth:`run`, pausing (yielding) after each ``every``
        processed instance facts, so that a caller can write what was derived so far (the
        log) while the rest is derived; ``None`` never pauses."""
        while self._schema_queue or self.queue:
            while self._schema_queue:
                process_schema(self, *self._schema_queue.pop())
            if self._passed_generation != self._schema_generation:
                self._passed_generation = self._schema_generation
                schema_pass(self)
                if self._schema_queue:
                    continue
            if self._cached_generation != self._schema_generation:
                self.property_cache.clear()
                self.class_cache.clear()
                self._cached_generation = self._schema_generation
            type_info = self.property_cache.get(TYPE) or property_info(self, TYPE)
            self._quiet = not (self.fact_hooks or type_info.active or self.sp.get(SAME_AS))
            queue, schema_queue, process = self.queue, self._schema_queue, self._process
            if every is None:
                while queue and not schema_queue:
                    s, p, o = queue.pop()
                    process(s, p, o)
            else:
                while queue and not schema_queue:
                    for _ in range(min(every, len(queue))):
                        s, p, o = queue.pop()
                        process(s, p, o)
                        if schema_queue:
                            break
                    yield
            self.instances_processed = True

    # Schema rules -----------------------------------------------------------------------------

    def list_items(self, head: str) -> list[str]:
        """The members of the RDF list starting at ``head`` (stops at a cycle or a gap)."""
        items, seen, node = [], set(), head
        while node != NIL and node not in seen:
            seen.add(node)
            firsts = self.objects(node, FIRST)
            rests = self.objects(node, REST)
            if not firsts or not rests:
                break
            items.append(min(firsts))
            node = min(rests)
        return items

    def list_positions(self, head: str) -> list[set[str]]:
        """Every value at each position of a list (equality can give a position several)."""
        positions, seen, node = [], set(), head
        while node != NIL and node not in seen:
            seen.add(node)
            firsts, rests = self.objects(node, FIRST), self.objects(node, REST)
            if not firsts or not rests:
                break
            positions.append(set(firsts))
            node = min(rests)
        return positions

    def requeue(self, terms: set[str]) -> None:
        """Process again the instance facts whose predicate or class is one of ``terms``."""
        queue = self.queue
        for term in terms:
            for s, objects in self.sp.get(term, {}).items():
                queue.extend((s, term, o) for o in objects)
            queue.extend((x, TYPE, term) for x in self.subjects(TYPE, term))

    # Instance rules ---------------------------------------------------------------------------

    def _process(self, s: str, p: str, o: str) -> None:
        add = self.add
        same = self.sp.get(SAME_AS)
        if same:  # eq-rep-s, eq-rep-p, eq-rep-o
            for s2 in list(same.get(s, ())):
                add(s2, p, o)
            for o2 in list(same.get(o, ())):
                add(s, p, o2)
            for p2 in list(same.get(p, ())):
                add(s, p2, o)
        if p == SAME_AS:
            self._same_as(s, o)
        info = self.property_cache.get(p) or property_info(self, p)
        if info.active:
            sp = self.sp
            if info.domains:  # prp-dom (most are known: look before calling add)
                known = sp[TYPE].get(s, _EMPTY) if TYPE in sp else _EMPTY
                for c in info.domains:
                    if c not in known:
                        add(s, TYPE, c)
            if info.ranges:  # prp-rng
                known = sp[TYPE].get(o, _EMPTY) if TYPE in sp else _EMPTY
                for c in info.ranges:
                    if c not in known:
                        add(o, TYPE, c)
            for q in info.supers:  # prp-spo1, prp-eqp1, prp-eqp2
                add(s, q, o)
            for q in info.inverses:  # prp-inv1, prp-inv2
                if s not in sp.get(q, {}).get(o, _EMPTY):
                    add(o, q, s)
            if info.symmetric and s not in sp[p].get(o, _EMPTY):  # prp-symp
                add(o, p, s)
            if info.transitive:  # prp-trp, from either premise
                by_subject, by_object = self.sp[p], self.op[p]
                for z in list(by_subject.get(o, ())):
                    add(s, p, z)
                for w in list(by_object.get(s, ())):
                    add(w, p, o)
            if info.functional:  # prp-fp
                for o2 in list(self.sp[p].get(s, ())):
                    if o2 != o:
                        add(o, SAME_AS, o2)
                        add(o2, SAME_AS, o)
            if info.inverse_functional:  # prp-ifp
                for s2 in list(self.op[p].get(o, ())):
                    if s2 != s:
                        add(s, SAME_AS, s2)
                        add(s2, SAME_AS, s)
            if info.restrictions:
                self._restrictions_forward(s, p, o, info.restrictions)
            for chain_property, chain, position in info.chains:  # prp-spo2
                for start in self.walk_back(s, chain[:position]):
                    for end in self.walk(o, chain[position + 1 :]):
                        add(start, chain_property, end)
        if p == TYPE:
            self._type(s, o)
        for hook in self.fact_hooks:
            hook(self, s, p, o)

    def _same_as(self, x: str, y: str) -> None:
        self._quiet = False  # from now on every type fact is processed (eq-rep)
        add = self.add
        if x[0] == '"' and x not in self._equated_literals:
            self._equate_literal(x)
        if x[0] == '"' and y[0] == '"':
            kx, ky = value_key(x), value_key(y)
            if kx is not None and ky is not None and kx != ky:
                self.unequal_same.add((min(x, y), max(x, y)))
        add(y, SAME_AS, x)  # eq-sym
        for z in list(self.objects(y, SAME_AS)):  # eq-trans
            if z != x:
                add(x, SAME_AS, z)
        for w in list(self.subjects(SAME_AS, x)):
            if w != y:
                add(w, SAME_AS, y)
        for q in list(self.sp):  # eq-rep-s, eq-rep-o, eq-rep-p for the facts already known
            for o in list(self.sp[q].get(x, ())):
                add(y, q, o)
            for s in list(self.op[q].get(x, ())):
                add(s, q, y)
        for s, objects in list(self.sp.get(x, {}).items()):
            for o in list(objects):
                add(s, y, o)

    def _restrictions_forward(
        self, s: str, p: str, o: str, restrictions: tuple[tuple[str, str, str | None], ...]
    ) -> None:
        add = self.add
        types = self.sp.get(TYPE, {})
        for restriction, kind, argument in restrictions:
            if kind == "svf":  # cls-svf1, cls-svf2
                if argument == THING or argument in types.get(o, _EMPTY):
                    add(s, TYPE, restriction)
            elif kind == "hv":  # cls-hv2
                if o == argument:
                    add(s, TYPE, restriction)
            elif restriction in types.get(s, _EMPTY):
                if kind == "avf":  # cls-avf
                    assert argument is not None
                    add(o, TYPE, argument)
                else:  # cls-maxc2, cls-maxqc3, cls-maxqc4
                    self._max_one(s, p, argument)

    def _max_one(self, u: str, p: str, on_class: str | None) -> None:
        types = self.sp.get(TYPE, {})
        values = [
            y
            for y in self.sp.get(p, {}).get(u, ())
            if on_class is None or on_class == THING or on_class in types.get(y, _EMPTY)
        ]
        for y1 in values:
            for y2 in values:
                if y1 != y2:
                    self.add(y1, SAME_AS, y2)

    def _type(self, x: str, c: str) -> None:
        add = self.add
        info = self.class_cache.get(c) or class_info(self, c)
        types = self.sp[TYPE][x]
        if info.supers:  # cax-sco, cax-eqc1, cax-eqc2
            if self._quiet:
                if info.quiet_supers is None:
                    self._split_supers(info)
                    assert info.quiet_supers is not None
                # Processing (x type d) for a "quiet" d could only re-add d's super-classes,
                # which are c's too (the hierarchy is closed): record it and skip the queue.
                new = info.quiet_supers - types
                if new:
                    types |= new
                    by_class, log = self.op[TYPE], self._log
                    for d in new:
                        members = by_class.get(d)
                        if members is None:
                            by_class[d] = {x}
                        else:
                            members.add(x)
                        log.append((x, TYPE, d))
                for d in info.loud_supers:
                    if d not in types:
                        add(x, TYPE, d)
            else:
                for d in info.supers:
                    if d not in types:
                        add(x, TYPE, d)
        if not info.more:
            return
        for d in info.parts:  # cls-int2
            if d not in types:
                add(x, TYPE, d)
        for intersection, parts in info.in_intersections:  # cls-int1
            if intersection not in types and all(part in types for part in parts):
                add(x, TYPE, intersection)
        for union in info.in_unions:  # cls-uni
            if union not in types:
                add(x, TYPE, union)
        for restriction, prop in info.filler_of:  # cls-svf1 from the value's side
            for u in list(self.op.get(prop, {}).get(x, ())):
                add(u, TYPE, restriction)
        for prop, filler in info.all_values:  # cls-avf from the restriction's side
            for v in list(self.sp.get(prop, {}).get(x, ())):
                add(v, TYPE, filler)
        for prop, value in info.has_values:  # cls-hv1
            add(x, prop, value)
        for prop, on_class in info.max_one:  # cls-maxc2, cls-maxqc3/4
            self._max_one(x, prop, on_class)
        for restriction, prop in info.max_one_class_of:  # cls-maxqc3 from a value's side
            for u in list(self.op.get(prop, {}).get(x, ())):
                if restriction in self.objects(u, TYPE):
                    self._max_one(u, prop, c)

    def _split_supers(self, info: ClassInfo) -> None:
        """Split a class's super-classes into those with no rule of their own and the rest (a
        datatype has one: dt-not-type checks each literal typed with it)."""
        quiet = set()
        for d in info.supers:
            other = self.class_cache.get(d) or class_info(self, d)
            if not other.more and d not in SCHEMA_TYPES and d not in RL_DATATYPES:
                quiet.add(d)
        info.quiet_supers = frozenset(quiet)
        info.loud_supers = tuple(d for d in info.supers if d not in quiet)

    def walk(self, start: str, chain: tuple[str, ...]) -> set[str]:
        frontier = {start}
        for prop in chain:
            index = self.sp.get(prop, {})
            frontier = {n for node in frontier for n in index.get(node, ())}
            if not frontier:
                break
        return frontier

    def walk_back(self, end: str, chain: tuple[str, ...]) -> set[str]:
        frontier = {end}
        for prop in reversed(chain):
            index = self.op.get(prop, {})
            frontier = {n for node in frontier for n in index.get(node, ())}
            if not frontier:
                break
        return frontier

    # Schema caches ----------------------------------------------------------------------------
