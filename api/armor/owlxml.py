"""OWL/XML (the syntax Protégé saves as "OWL/XML") to RDF triples, by the OWL 2 RDF mapping.

Each axiom element becomes the triples of its mapping in "OWL 2 Web Ontology Language: Mapping to
RDF Graphs", class expressions and lists as blank nodes, SWRL rules (``DLSafeRule``) as the SWRL
RDF vocabulary, and axiom annotations as ``owl:Axiom`` reifications. An element this reader does
not know raises :class:`OwlXmlError` naming it: nothing is dropped silently.

>>> doc = b'''<Ontology xmlns="http://www.w3.org/2002/07/owl#" xml:base="http://ex.org/o"
...   ontologyIRI="http://ex.org/o"><Declaration><Class IRI="#A"/></Declaration>
...   <SubClassOf><Class IRI="#A"/><Class abbreviatedIRI="owl:Thing"/></SubClassOf></Ontology>'''
>>> [str(t) for t in owlxml_triples(doc)][1:]  # doctest: +NORMALIZE_WHITESPACE
['<http://ex.org/o#A> <http://www.w3.org/1999/02/22-rdf-syntax-ns#type> <http://www.w3.org/2002/07/owl#Class>',
 '<http://ex.org/o#A> <http://www.w3.org/2000/01/rdf-schema#subClassOf> <http://www.w3.org/2002/07/owl#Thing>']
"""

import xml.etree.ElementTree as ET
from collections.abc import Callable
from urllib.parse import urljoin

from pyoxigraph import BlankNode, Literal, NamedNode, Triple

from kg.errors import InvalidInputError
from ontologies.vocab import OWL_NS, RDF_NS, RDFS_NS, SWRL_NS, XSD_NS

__all__ = ["OwlXmlError", "owlxml_triples"]

XML_NS = "{http://www.w3.org/XML/1998/namespace}"
Term = NamedNode | BlankNode | Literal
Node = NamedNode | BlankNode


class OwlXmlError(InvalidInputError):
    """The document is not OWL/XML, or holds an element this reader cannot map."""


def _n(namespace: str, name: str) -> NamedNode:
    return NamedNode(namespace + name)


TYPE = _n(RDF_NS, "type")
FIRST, REST, NIL = _n(RDF_NS, "first"), _n(RDF_NS, "rest"), _n(RDF_NS, "nil")
_DECLARED = {
    "Class": _n(OWL_NS, "Class"),
    "Datatype": _n(RDFS_NS, "Datatype"),
    "ObjectProperty": _n(OWL_NS, "ObjectProperty"),
    "DataProperty": _n(OWL_NS, "DatatypeProperty"),
    "AnnotationProperty": _n(OWL_NS, "AnnotationProperty"),
    "NamedIndividual": _n(OWL_NS, "NamedIndividual"),
}
_CHARACTERISTICS = {
    "FunctionalObjectProperty": "FunctionalProperty",
    "FunctionalDataProperty": "FunctionalProperty",
    "InverseFunctionalObjectProperty": "InverseFunctionalProperty",
    "ReflexiveObjectProperty": "ReflexiveProperty",
    "IrreflexiveObjectProperty": "IrreflexiveProperty",
    "SymmetricObjectProperty": "SymmetricProperty",
    "AsymmetricObjectProperty": "AsymmetricProperty",
    "TransitiveObjectProperty": "TransitiveProperty",
}
_PAIRS = {  # axiom -> predicate between its two (or first and each further) operands
    "SubClassOf": _n(RDFS_NS, "subClassOf"),
    "SubObjectPropertyOf": _n(RDFS_NS, "subPropertyOf"),
    "SubDataPropertyOf": _n(RDFS_NS, "subPropertyOf"),
    "SubAnnotationPropertyOf": _n(RDFS_NS, "subPropertyOf"),
    "ObjectPropertyDomain": _n(RDFS_NS, "domain"),
    "DataPropertyDomain": _n(RDFS_NS, "domain"),
    "AnnotationPropertyDomain": _n(RDFS_NS, "domain"),
    "ObjectPropertyRange": _n(RDFS_NS, "range"),
    "DataPropertyRange": _n(RDFS_NS, "range"),
    "AnnotationPropertyRange": _n(RDFS_NS, "range"),
    "InverseObjectProperties": _n(OWL_NS, "inverseOf"),
    "DatatypeDefinition": _n(OWL_NS, "equivalentClass"),
    "EquivalentClasses": _n(OWL_NS, "equivalentClass"),
    "EquivalentObjectProperties": _n(OWL_NS, "equivalentProperty"),
    "EquivalentDataProperties": _n(OWL_NS, "equivalentProperty"),
    "SameIndividual": _n(OWL_NS, "sameAs"),
}
_NARY = {  # axiom -> (predicate for two operands, class of the n-ary node, its list predicate)
    "DisjointClasses": ("disjointWith", "AllDisjointClasses", "members"),
    "DisjointObjectProperties": ("propertyDisjointWith", "AllDisjointProperties", "members"),
    "DisjointDataProperties": ("propertyDisjointWith", "AllDisjointProperties", "members"),
    "DifferentIndividuals": ("differentFrom", "AllDifferent", "members"),
}
_RESTRICTIONS = {
    "ObjectSomeValuesFrom": "someValuesFrom",
    "ObjectAllValuesFrom": "allValuesFrom",
    "ObjectHasValue": "hasValue",
    "DataSomeValuesFrom": "someValuesFrom",
    "DataAllValuesFrom": "allValuesFrom",
    "DataHasValue": "hasValue",
}
_CARDINALITIES = {
    "Min": ("minCardinality", "minQualifiedCardinality"),
    "Max": ("maxCardinality", "maxQualifiedCardinality"),
    "Exact": ("cardinality", "qualifiedCardinality"),
}
_ENTITY_TAGS = {"Class", "Datatype", "ObjectProperty", "DataProperty", "AnnotationProperty"}
_ATOMS = {
    "ClassAtom": "ClassAtom",
    "DataRangeAtom": "DataRangeAtom",
    "ObjectPropertyAtom": "IndividualPropertyAtom",
    "DataPropertyAtom": "DatavaluedPropertyAtom",
    "SameIndividualAtom": "SameIndividualAtom",
    "DifferentIndividualsAtom": "DifferentIndividualsAtom",
    "BuiltInAtom": "BuiltinAtom",
}


def _local(element: ET.Element) -> str:
    tag = element.tag
    if not tag.startswith("{" + OWL_NS + "}"):
        raise OwlXmlError(f"element {tag!r} is not in the OWL namespace")
    return tag[len(OWL_NS) + 2 :]


class _Reader:
    def __init__(self, root: ET.Element) -> None:
        self.base = root.get(XML_NS + "base") or root.get("ontologyIRI") or ""
        self.prefixes = {
            "owl": OWL_NS,
            "rdf": RDF_NS,
            "rdfs": RDFS_NS,
            "xsd": XSD_NS,
            "xml": "http://www.w3.org/XML/1998/namespace",
        }
        self.triples: list[Triple] = []
        self.anonymous: dict[str, BlankNode] = {}

    def add(self, s: Node, p: NamedNode, o: Term) -> Triple:
        triple = Triple(s, p, o)
        self.triples.append(triple)
        return triple

    # Names and values ----------------------------------------------------------------------------

    def iri(self, element: ET.Element) -> NamedNode:
        if (value := element.get("IRI")) is not None:
            return NamedNode(urljoin(self.base, value) if self.base else value)
        if (value := element.get("abbreviatedIRI")) is not None:
            prefix, _, local = value.partition(":")
            if prefix not in self.prefixes:
                raise OwlXmlError(f"abbreviatedIRI {value!r}: prefix {prefix!r} is not declared")
            return NamedNode(self.prefixes[prefix] + local)
        if _local(element) in ("IRI", "AbbreviatedIRI"):
            return self.iri_text(element)
        raise OwlXmlError(f"<{_local(element)}> has neither IRI nor abbreviatedIRI")

    def iri_text(self, element: ET.Element) -> NamedNode:
        text = (element.text or "").strip()
        if _local(element) == "AbbreviatedIRI":
            prefix, _, local = text.partition(":")
            if prefix not in self.prefixes:
                raise OwlXmlError(f"AbbreviatedIRI {text!r}: prefix {prefix!r} is not declared")
            return NamedNode(self.prefixes[prefix] + local)
        return NamedNode(urljoin(self.base, text) if self.base else text)

    def literal(self, element: ET.Element) -> Literal:
        text = element.text or ""
        language = element.get(XML_NS + "lang")
        datatype = element.get("datatypeIRI")
        if language:
            return Literal(text, language=language)
        if datatype is None or datatype == RDF_NS + "PlainLiteral":
            return Literal(text)
        return Literal(text, datatype=NamedNode(urljoin(self.base, datatype)))

    def individual(self, element: ET.Element) -> Node:
        tag = _local(element)
        if tag == "AnonymousIndividual":
            node_id = element.get("nodeID", "")
            return self.anonymous.setdefault(node_id, BlankNode())
        if tag in ("NamedIndividual", "Variable"):
            return self.iri(element)
        raise OwlXmlError(f"<{tag}>: expected an individual")

    def value(self, element: ET.Element) -> Term:
        """An annotation value or subject, a literal, or an individual."""
        tag = _local(element)
        if tag == "Literal":
            return self.literal(element)
        if tag in ("IRI", "AbbreviatedIRI"):
            return self.iri_text(element)
        return self.individual(element)

    def items(self, terms: list[Term], item_type: NamedNode | None = None) -> Node:
        head: Node = NIL
        for term in reversed(terms):
            cell = BlankNode()
            if item_type is not None:
                self.add(cell, TYPE, item_type)
            self.add(cell, FIRST, term)
            self.add(cell, REST, head)
            head = cell
        return head

    # Expressions ---------------------------------------------------------------------------------

    def expression(self, element: ET.Element) -> Term:
        """A class expression, data range, property expression, individual or literal."""
        tag = _local(element)
        if tag in _ENTITY_TAGS:
            return self.iri(element)
        if tag in ("NamedIndividual", "AnonymousIndividual", "Variable"):
            return self.individual(element)
        if tag == "Literal":
            return self.literal(element)
        children = list(element)
        node = BlankNode()
        if tag in ("ObjectInverseOf", "DataInverseOf"):
            self.add(node, _n(OWL_NS, "inverseOf"), self.expression(children[0]))
            return node
        if tag in ("ObjectIntersectionOf", "ObjectUnionOf", "DataIntersectionOf", "DataUnionOf"):
            kind = "Class" if tag.startswith("Object") else "Datatype"
            self.add(node, TYPE, _DECLARED[kind])
            predicate = "intersectionOf" if "Intersection" in tag else "unionOf"
            operands = [self.expression(c) for c in children]
            self.add(node, _n(OWL_NS, predicate), self.items(operands))
            return node
        if tag == "ObjectComplementOf":
            self.add(node, TYPE, _DECLARED["Class"])
            self.add(node, _n(OWL_NS, "complementOf"), self.expression(children[0]))
            return node
        if tag == "DataComplementOf":
            self.add(node, TYPE, _DECLARED["Datatype"])
            self.add(node, _n(OWL_NS, "datatypeComplementOf"), self.expression(children[0]))
            return node
        if tag in ("ObjectOneOf", "DataOneOf"):
            kind = "Class" if tag == "ObjectOneOf" else "Datatype"
            self.add(node, TYPE, _DECLARED[kind])
            self.add(node, _n(OWL_NS, "oneOf"), self.items([self.expression(c) for c in children]))
            return node
        if tag == "DatatypeRestriction":
            self.add(node, TYPE, _DECLARED["Datatype"])
            self.add(node, _n(OWL_NS, "onDatatype"), self.expression(children[0]))
            facets: list[Term] = []
            for facet in children[1:]:
                cell = BlankNode()
                self.add(cell, NamedNode(facet.get("facet", "")), self.literal(facet[0]))
                facets.append(cell)
            self.add(node, _n(OWL_NS, "withRestrictions"), self.items(facets))
            return node
        self.add(node, TYPE, _n(OWL_NS, "Restriction"))
        if tag in _RESTRICTIONS:
            self.add(node, _n(OWL_NS, "onProperty"), self.expression(children[0]))
            self.add(node, _n(OWL_NS, _RESTRICTIONS[tag]), self.expression(children[1]))
            return node
        if tag == "ObjectHasSelf":
            self.add(node, _n(OWL_NS, "onProperty"), self.expression(children[0]))
            self.add(node, _n(OWL_NS, "hasSelf"), Literal(True))
            return node
        for bound, (plain, qualified) in _CARDINALITIES.items():
            if tag in (f"Object{bound}Cardinality", f"Data{bound}Cardinality"):
                count = Literal(
                    element.get("cardinality", "0"), datatype=_n(XSD_NS, "nonNegativeInteger")
                )
                self.add(node, _n(OWL_NS, "onProperty"), self.expression(children[0]))
                if len(children) > 1:
                    self.add(node, _n(OWL_NS, qualified), count)
                    on = "onClass" if tag.startswith("Object") else "onDataRange"
                    self.add(node, _n(OWL_NS, on), self.expression(children[1]))
                else:
                    self.add(node, _n(OWL_NS, plain), count)
                return node
        raise OwlXmlError(f"<{tag}> is not an OWL/XML class expression or data range")

    # Axioms --------------------------------------------------------------------------------------

    def axiom(self, element: ET.Element) -> None:
        tag = _local(element)
        annotations = [c for c in element if _local(c) == "Annotation"]
        operands = [c for c in element if _local(c) != "Annotation"]
        main = self._axiom(tag, operands)
        if annotations and main is not None:
            node = BlankNode()
            self.add(node, TYPE, _n(OWL_NS, "Axiom"))
            self.add(node, _n(OWL_NS, "annotatedSource"), self._term(main.subject))
            self.add(node, _n(OWL_NS, "annotatedProperty"), main.predicate)
            self.add(node, _n(OWL_NS, "annotatedTarget"), self._term(main.object))
            for annotation in annotations:
                self.annotation(node, annotation)

    def annotation(self, subject: Node, element: ET.Element) -> None:
        parts = [c for c in element if _local(c) != "Annotation"]
        self.add(subject, self.iri(parts[0]), self.value(parts[1]))

    def _axiom(self, tag: str, ops: list[ET.Element]) -> Triple | None:
        if tag == "Declaration":
            entity = ops[0]
            return self.add(self.iri(entity), TYPE, _DECLARED[_local(entity)])
        if tag in _CHARACTERISTICS:
            return self.add(self._node(ops[0]), TYPE, _n(OWL_NS, _CHARACTERISTICS[tag]))
        if tag == "SubObjectPropertyOf" and _local(ops[0]) == "ObjectPropertyChain":
            chain = [self.expression(c) for c in ops[0]]
            return self.add(self._node(ops[1]), _n(OWL_NS, "propertyChainAxiom"), self.items(chain))
        if tag in _PAIRS:
            first = self._node(ops[0])
            main = None
            for other in ops[1:]:
                main = self.add(first, _PAIRS[tag], self.expression(other))
            return main
        if tag in _NARY:
            pair, kind, members = _NARY[tag]
            terms = [self.expression(c) for c in ops]
            if len(terms) == 2:
                return self.add(self._as_node(terms[0]), _n(OWL_NS, pair), terms[1])
            node = BlankNode()
            self.add(node, TYPE, _n(OWL_NS, kind))
            if tag == "DifferentIndividuals":
                members = "distinctMembers"
            self.add(node, _n(OWL_NS, members), self.items(terms))
            return None
        if tag == "DisjointUnion":
            terms = [self.expression(c) for c in ops[1:]]
            return self.add(self.iri(ops[0]), _n(OWL_NS, "disjointUnionOf"), self.items(terms))
        if tag == "HasKey":
            keys = [self.expression(c) for c in ops[1:]]
            return self.add(self._node(ops[0]), _n(OWL_NS, "hasKey"), self.items(keys))
        if tag == "ClassAssertion":
            return self.add(self.individual(ops[1]), TYPE, self.expression(ops[0]))
        if tag in ("ObjectPropertyAssertion", "DataPropertyAssertion"):
            if _local(ops[0]) == "ObjectInverseOf":
                prop = self.iri(ops[0][0])
                return self.add(self.individual(ops[2]), prop, self.individual(ops[1]))
            return self.add(self.individual(ops[1]), self.iri(ops[0]), self.value(ops[2]))
        if tag in ("NegativeObjectPropertyAssertion", "NegativeDataPropertyAssertion"):
            node = BlankNode()
            target = "targetIndividual" if tag.startswith("NegativeObject") else "targetValue"
            self.add(node, TYPE, _n(OWL_NS, "NegativePropertyAssertion"))
            self.add(node, _n(OWL_NS, "sourceIndividual"), self.individual(ops[1]))
            self.add(node, _n(OWL_NS, "assertionProperty"), self.expression(ops[0]))
            self.add(node, _n(OWL_NS, target), self.value(ops[2]))
            return None
        if tag == "AnnotationAssertion":
            subject = self.value(ops[1])
            if isinstance(subject, Literal):
                raise OwlXmlError("AnnotationAssertion: the subject cannot be a literal")
            return self.add(subject, self.iri(ops[0]), self.value(ops[2]))
        if tag == "DLSafeRule":
            self.rule(ops)
            return None
        raise OwlXmlError(f"<{tag}> is not an OWL/XML axiom this reader knows")

    def _node(self, element: ET.Element) -> Node:
        return self._as_node(self.expression(element))

    @staticmethod
    def _term(term: object) -> Term:
        if not isinstance(term, NamedNode | BlankNode | Literal):
            raise OwlXmlError(f"cannot annotate an axiom about {term}")
        return term

    @staticmethod
    def _as_node(term: Term) -> Node:
        if isinstance(term, Literal):
            raise OwlXmlError(f"a literal ({term}) cannot be the subject of an axiom")
        return term

    # SWRL ----------------------------------------------------------------------------------------

    def rule(self, parts: list[ET.Element]) -> None:
        node = BlankNode()
        self.add(node, TYPE, _n(SWRL_NS, "Imp"))
        for part in parts:
            which = {"Body": "body", "Head": "head"}.get(_local(part))
            if which is None:
                raise OwlXmlError(f"<DLSafeRule> holds <{_local(part)}>, expected Body and Head")
            atoms: list[Term] = [self.atom(a) for a in part]
            self.add(node, _n(SWRL_NS, which), self.items(atoms, _n(SWRL_NS, "AtomList")))

    def atom(self, element: ET.Element) -> Node:
        tag = _local(element)
        if tag not in _ATOMS:
            raise OwlXmlError(f"<{tag}> is not a SWRL atom")
        node = BlankNode()
        self.add(node, TYPE, _n(SWRL_NS, _ATOMS[tag]))
        children = list(element)
        args: list[Term] = [self.argument(c) for c in children]
        if tag == "BuiltInAtom":
            self.add(node, _n(SWRL_NS, "builtin"), self.iri(element))
            self.add(node, _n(SWRL_NS, "arguments"), self.items(args))
            return node
        predicate = {
            "ClassAtom": "classPredicate",
            "DataRangeAtom": "dataRange",
            "ObjectPropertyAtom": "propertyPredicate",
            "DataPropertyAtom": "propertyPredicate",
        }.get(tag)
        if predicate is not None:
            self.add(node, _n(SWRL_NS, predicate), self.expression(children[0]))
            args = args[1:]
        for index, arg in enumerate(args, start=1):
            self.add(node, _n(SWRL_NS, f"argument{index}"), arg)
        return node

    def argument(self, element: ET.Element) -> Term:
        if _local(element) == "Variable":
            variable = self.iri(element)
            self.add(variable, TYPE, _n(SWRL_NS, "Variable"))
            return variable
        return self.expression(element)


_Handler = Callable[[_Reader, ET.Element], None]


def owlxml_triples(content: bytes) -> list[Triple]:
    """The RDF triples of an OWL/XML document (blank nodes as pyoxigraph blank nodes).

    Raises :class:`OwlXmlError` for malformed XML, a root other than ``Ontology``, an element out
    of place, or an element this reader does not know.
    """
    try:
        root = ET.fromstring(content)
    except ET.ParseError as error:
        raise OwlXmlError(f"not well-formed XML: {error}") from None
    if root.tag != "{" + OWL_NS + "}Ontology":
        raise OwlXmlError(f"the root element is {root.tag!r}, expected OWL's <Ontology>")
    reader = _Reader(root)
    ontology = root.get("ontologyIRI")
    header: Node = NamedNode(ontology) if ontology else BlankNode()
    reader.add(header, TYPE, _n(OWL_NS, "Ontology"))
    if version := root.get("versionIRI"):
        reader.add(header, _n(OWL_NS, "versionIRI"), NamedNode(version))
    for element in root:
        tag = _local(element)
        try:
            if tag == "Prefix":
                reader.prefixes[element.get("name", "")] = element.get("IRI", "")
            elif tag == "Import":
                reader.add(header, _n(OWL_NS, "imports"), reader.iri_text(element))
            elif tag == "Annotation":
                reader.annotation(header, element)
            else:
                reader.axiom(element)
        except (IndexError, KeyError):
            raise OwlXmlError(f"<{tag}> is missing an operand") from None
        except ValueError as error:
            if isinstance(error, OwlXmlError):
                raise
            raise OwlXmlError(f"<{tag}>: {error}") from None
    return reader.triples
