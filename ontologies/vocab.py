"""IRIs of Engram's terms, named graphs and the W3C vocabularies it reuses.

Every IRI the code uses is a constant here, so that a rename happens in one place.
"""

from pyoxigraph import NamedNode

BASE = "https://w3id.org/engram/"
ENGRAM_NS = BASE + "ontology#"
ONTOLOGY_IRI = NamedNode(BASE + "ontology")
EXPORT_ONTOLOGY_IRI = NamedNode(BASE + "export")
SKOLEM_PREFIX = BASE + ".well-known/genid/"
"""Blank nodes are stored as IRIs under this prefix (RDF 1.1 skolem IRIs) and exported as blank
nodes again, so that OWL class expressions stay precisely deletable inside the store."""

RDF_NS = "http://www.w3.org/1999/02/22-rdf-syntax-ns#"
RDFS_NS = "http://www.w3.org/2000/01/rdf-schema#"
OWL_NS = "http://www.w3.org/2002/07/owl#"
XSD_NS = "http://www.w3.org/2001/XMLSchema#"
PROV_NS = "http://www.w3.org/ns/prov#"
DCTERMS_NS = "http://purl.org/dc/terms/"

PREFIXES = {
    "engram": ENGRAM_NS,
    "rdf": RDF_NS,
    "rdfs": RDFS_NS,
    "owl": OWL_NS,
    "xsd": XSD_NS,
    "prov": PROV_NS,
    "dcterms": DCTERMS_NS,
}


def engram(name: str) -> NamedNode:
    """The IRI of an Engram term by local name: ``engram("Sphere")``."""
    return NamedNode(ENGRAM_NS + name)


# Named graphs (DESIGN.md, "Store layout").
GRAPH_NS = BASE + "graph/"
TBOX = NamedNode(GRAPH_NS + "tbox")
MEMORY = NamedNode(GRAPH_NS + "memory")
EPISODIC = NamedNode(GRAPH_NS + "episodic")
TRASH = NamedNode(GRAPH_NS + "trash")
EPISODES = NamedNode(GRAPH_NS + "episodes")
GRAPHS = {
    "tbox": TBOX,
    "memory": MEMORY,
    "episodic": EPISODIC,
    "trash": TRASH,
    "episodes": EPISODES,
}


def reference_graph(name: str, *, inferred: bool = False) -> NamedNode:
    """The named graph of an ARMOR reference (asserted, or the triples its REASON inferred)."""
    return NamedNode(GRAPH_NS + "ref/" + name + ("/inferred" if inferred else ""))


# RDF, RDFS, OWL, XSD terms used in code.
RDF_TYPE = NamedNode(RDF_NS + "type")
RDF_FIRST = NamedNode(RDF_NS + "first")
RDF_REST = NamedNode(RDF_NS + "rest")
RDF_NIL = NamedNode(RDF_NS + "nil")
RDFS_LABEL = NamedNode(RDFS_NS + "label")
RDFS_COMMENT = NamedNode(RDFS_NS + "comment")
RDFS_SUBCLASSOF = NamedNode(RDFS_NS + "subClassOf")
RDFS_SEEALSO = NamedNode(RDFS_NS + "seeAlso")
OWL_ONTOLOGY = NamedNode(OWL_NS + "Ontology")
OWL_VERSION_IRI = NamedNode(OWL_NS + "versionIRI")
OWL_VERSION_INFO = NamedNode(OWL_NS + "versionInfo")
OWL_CLASS = NamedNode(OWL_NS + "Class")
OWL_NAMED_INDIVIDUAL = NamedNode(OWL_NS + "NamedIndividual")
OWL_OBJECT_PROPERTY = NamedNode(OWL_NS + "ObjectProperty")
OWL_DATATYPE_PROPERTY = NamedNode(OWL_NS + "DatatypeProperty")
OWL_ANNOTATION_PROPERTY = NamedNode(OWL_NS + "AnnotationProperty")
OWL_EQUIVALENT_CLASS = NamedNode(OWL_NS + "equivalentClass")
OWL_ON_CLASS = NamedNode(OWL_NS + "onClass")
OWL_ON_PROPERTY = NamedNode(OWL_NS + "onProperty")
OWL_RESTRICTION = NamedNode(OWL_NS + "Restriction")
OWL_INTERSECTION_OF = NamedNode(OWL_NS + "intersectionOf")
OWL_MIN_QUALIFIED_CARDINALITY = NamedNode(OWL_NS + "minQualifiedCardinality")
CARDINALITY_PREDICATES = frozenset(
    NamedNode(OWL_NS + name)
    for name in (
        "cardinality",
        "minCardinality",
        "maxCardinality",
        "qualifiedCardinality",
        "minQualifiedCardinality",
        "maxQualifiedCardinality",
    )
)
XSD_NON_NEGATIVE_INTEGER = NamedNode(XSD_NS + "nonNegativeInteger")
XSD_DATETIME = NamedNode(XSD_NS + "dateTime")
DCTERMS_CREATED = NamedNode(DCTERMS_NS + "created")

# Engram classes.
GEOMETRIC_PRIMITIVE = engram("GeometricPrimitive")
ORIENTABLE = engram("Orientable")
SPHERE = engram("Sphere")
CYLINDER = engram("Cylinder")
CONE = engram("Cone")
PLANE = engram("Plane")
PRIMITIVE_LEAF_TYPES = (SPHERE, CYLINDER, CONE, PLANE)
SCENE = engram("Scene")
TRASH_CLASS = engram("Trash")
MEMORY_POLICY = engram("MemoryPolicy")
DEFAULT_POLICY = engram("defaultPolicy")

# Spatial relations: primary relation -> its inverse (symmetric ones map to themselves).
SPATIAL_INVERSES = {
    engram("isRightOf"): engram("isLeftOf"),
    engram("isLeftOf"): engram("isRightOf"),
    engram("isBehindOf"): engram("isInFrontOf"),
    engram("isInFrontOf"): engram("isBehindOf"),
    engram("isAboveOf"): engram("isBelowOf"),
    engram("isBelowOf"): engram("isAboveOf"),
    **{
        engram(name): engram(name)
        for name in (
            "isParallelWith",
            "isPerpendicularWith",
            "isCoaxialWith",
            "isAlongXWith",
            "isAlongYWith",
            "isAlongZWith",
        )
    },
}

# Memory item annotations.
COMPLEXITY = engram("complexity")
STORE_COUNT = engram("storeCount")
RETRIEVE_COUNT = engram("retrieveCount")
SCORE = engram("score")
LEVEL = engram("level")
CREATED = engram("created")
LAST_ACCESSED = engram("lastAccessed")
CONSECUTIVE_WEAK_COUNT = engram("consecutiveWeakCount")
PINNED = engram("pinned")
SIGNATURE_SUBJECT_TYPE = engram("signatureSubjectType")
SIGNATURE_RELATION = engram("signatureRelation")
