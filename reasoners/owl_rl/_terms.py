"""The RDF, RDFS, OWL, XSD and SWRL terms the rules use, written as N-Triples terms.

The engine keeps every term as its N-Triples text (``<iri>`` or a literal such as
``"1"^^<http://www.w3.org/2001/XMLSchema#integer>``): that is what the store dumps, strings hash
fast, and the text goes back to the store without building term objects one by one.
"""

import re

from pyoxigraph import Literal, NamedNode

from ontologies.vocab import OWL_NS, RDF_NS, RDFS_NS, SWRL_NS, XSD_NS


def rdf(name: str) -> str:
    return f"<{RDF_NS}{name}>"


def rdfs(name: str) -> str:
    return f"<{RDFS_NS}{name}>"


def owl(name: str) -> str:
    return f"<{OWL_NS}{name}>"


def xsd(name: str) -> str:
    return f"<{XSD_NS}{name}>"


def swrl(name: str) -> str:
    return f"<{SWRL_NS}{name}>"


TYPE = rdf("type")
FIRST = rdf("first")
REST = rdf("rest")
NIL = rdf("nil")
PROPERTY = rdf("Property")
SUB_CLASS_OF = rdfs("subClassOf")
SUB_PROPERTY_OF = rdfs("subPropertyOf")
DOMAIN = rdfs("domain")
RANGE = rdfs("range")
DATATYPE = rdfs("Datatype")

THING = owl("Thing")
NOTHING = owl("Nothing")
CLASS = owl("Class")
OBJECT_PROPERTY = owl("ObjectProperty")
DATATYPE_PROPERTY = owl("DatatypeProperty")
ANNOTATION_PROPERTY = owl("AnnotationProperty")
SAME_AS = owl("sameAs")
DIFFERENT_FROM = owl("differentFrom")
ALL_DIFFERENT = owl("AllDifferent")
MEMBERS = owl("members")
DISTINCT_MEMBERS = owl("distinctMembers")
EQUIVALENT_CLASS = owl("equivalentClass")
EQUIVALENT_PROPERTY = owl("equivalentProperty")
INVERSE_OF = owl("inverseOf")
FUNCTIONAL = owl("FunctionalProperty")
INVERSE_FUNCTIONAL = owl("InverseFunctionalProperty")
IRREFLEXIVE = owl("IrreflexiveProperty")
SYMMETRIC = owl("SymmetricProperty")
ASYMMETRIC = owl("AsymmetricProperty")
TRANSITIVE = owl("TransitiveProperty")
PROPERTY_CHAIN = owl("propertyChainAxiom")
PROPERTY_DISJOINT_WITH = owl("propertyDisjointWith")
ALL_DISJOINT_PROPERTIES = owl("AllDisjointProperties")
ALL_DISJOINT_CLASSES = owl("AllDisjointClasses")
DISJOINT_WITH = owl("disjointWith")
INTERSECTION_OF = owl("intersectionOf")
UNION_OF = owl("unionOf")
COMPLEMENT_OF = owl("complementOf")
ONE_OF = owl("oneOf")
ON_PROPERTY = owl("onProperty")
ON_CLASS = owl("onClass")
SOME_VALUES_FROM = owl("someValuesFrom")
ALL_VALUES_FROM = owl("allValuesFrom")
HAS_VALUE = owl("hasValue")
MAX_CARDINALITY = owl("maxCardinality")
MAX_QUALIFIED_CARDINALITY = owl("maxQualifiedCardinality")
NEGATIVE_PROPERTY_ASSERTION = owl("NegativePropertyAssertion")
SOURCE_INDIVIDUAL = owl("sourceIndividual")
ASSERTION_PROPERTY = owl("assertionProperty")
TARGET_INDIVIDUAL = owl("targetIndividual")
TARGET_VALUE = owl("targetValue")
HAS_KEY = owl("hasKey")

ANNOTATION_PROPERTIES = (
    rdfs("label"),
    rdfs("comment"),
    rdfs("seeAlso"),
    rdfs("isDefinedBy"),
    owl("deprecated"),
    owl("versionInfo"),
    owl("priorVersion"),
    owl("backwardCompatibleWith"),
    owl("incompatibleWith"),
)
"""OWL 2 RL rule prp-ap: the built-in annotation properties."""


def literal_datatype(term: str) -> str | None:
    """The datatype IRI term of a typed literal, or None (IRIs, plain and language strings).

    >>> literal_datatype('"1"^^<http://www.w3.org/2001/XMLSchema#integer>')
    '<http://www.w3.org/2001/XMLSchema#integer>'
    >>> literal_datatype('"a"@en') is None
    True
    """
    if not term.startswith('"') or not term.endswith(">"):
        return None
    index = term.rfind('"^^<')
    return term[index + 3 :] if index > 0 else None


_ESCAPE = re.compile(r"\\(?:u([0-9A-Fa-f]{4})|U([0-9A-Fa-f]{8})|(.))")
_ESCAPES = {"t": "\t", "b": "\b", "n": "\n", "r": "\r", "f": "\f", '"': '"', "'": "'", "\\": "\\"}


def unescape(text: str) -> str:
    """The string an N-Triples string body stands for (``\\n``, ``\\"``, ``\\u00e9``...).

    >>> unescape('say \\\\"hi\\\\" \\\\u00e9')
    'say "hi" é'
    """

    def one(match: re.Match[str]) -> str:
        code = match.group(1) or match.group(2)
        return chr(int(code, 16)) if code else _ESCAPES.get(match.group(3), match.group(3))

    return _ESCAPE.sub(one, text) if "\\" in text else text


def to_term(text: str) -> NamedNode | Literal:
    """The pyoxigraph term an N-Triples IRI or literal stands for.

    >>> to_term('"1"^^<http://www.w3.org/2001/XMLSchema#integer>').value
    '1'
    >>> str(to_term('"chat"@fr'))
    '"chat"@fr'
    """
    if text.startswith("<"):
        return NamedNode(text[1:-1])
    end = text.rfind('"')
    lexical, rest = unescape(text[1:end]), text[end + 1 :]
    if rest.startswith("^^<"):
        return Literal(lexical, datatype=NamedNode(rest[3:-1]))
    if rest.startswith("@"):
        return Literal(lexical, language=rest[1:])
    return Literal(lexical)


def numeric_value(term: str) -> float | None:
    """The number a literal stands for (``"1"^^xsd:integer`` is 1), or None.

    >>> numeric_value('"2"^^<http://www.w3.org/2001/XMLSchema#nonNegativeInteger>')
    2.0
    """
    if not term.startswith('"') or literal_datatype(term) is None:
        return None
    try:
        return float(term[1 : term.rfind('"^^<')])
    except ValueError:
        return None
