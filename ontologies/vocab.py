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
SKOS_NS = "http://www.w3.org/2004/02/skos/core#"
SWRL_NS = "http://www.w3.org/2003/11/swrl#"
SWRLB_NS = "http://www.w3.org/2003/11/swrlb#"

PREFIXES = {
    "engram": ENGRAM_NS,
    "rdf": RDF_NS,
    "rdfs": RDFS_NS,
    "owl": OWL_NS,
    "xsd": XSD_NS,
    "prov": PROV_NS,
    "dcterms": DCTERMS_NS,
    "skos": SKOS_NS,
}
SKOS_NOTATION = NamedNode(SKOS_NS + "notation")
"""A learned class's short name (``Scene-7``); its rdfs:label says what it holds."""


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
HISTORY = NamedNode(GRAPH_NS + "history")
"""The scene memory's events (reasoners.history), reached by name like the trash."""
GRAPHS = {
    "tbox": TBOX,
    "memory": MEMORY,
    "episodic": EPISODIC,
    "trash": TRASH,
    "episodes": EPISODES,
    "history": HISTORY,
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
SCORE = engram("rawScore")
"""Raw ζ as of the class's last learn, store, retrieval or restore (a sleep pass leaves it; the
live values: the view)."""
CLASS_SIGNATURE = engram("signature")
LEVEL = engram("sleepLevel")
"""On a class or experienced scene in the trash: its level when it was forgotten (WEAK); on live
ones, in stores written before :data:`SLEEP_LEVELS` (migrated when the memory opens)."""
SLEEP_LEVELS = engram("sleepLevels")
"""On the memory state: the level the last sleep pass gave each live class and experienced
scene (what the next pass compares with), "<level> <IRI>" lines, zlib + base64."""
LEGACY_SCORE, LEGACY_LEVEL = engram("score"), engram("level")
"""Their names before the view: a store written then loses them when the memory opens."""
SCORE_TERMS = engram("scoreTerms")
"""Z_d, Z_s, Z_r packed in one string ("Z_d Z_s Z_r"), in stores written before
:data:`SCORE_TERM_PROPERTIES` (migrated when the memory opens)."""
SCORE_TERM_PROPERTIES = (
    engram("scoreTermComplexity"),
    engram("scoreTermStore"),
    engram("scoreTermRetrieve"),
)
"""Z_d, Z_s, Z_r of a class (reasoners.model), its raw terms kept exact by every update, each
an xsd:double."""
SCORE_FACTORS = (
    engram("scoreFactorComplexity"),
    engram("scoreFactorStore"),
    engram("scoreFactorRetrieve"),
)
"""On the memory state: the factors that turn Z_d, Z_s, Z_r into raw ζ with today's maxima."""
MAX_RAW_SCORE = engram("maxRawScore")
"""On the memory state: the largest raw ζ, which normalises scores."""
USES_POLICY = engram("usesPolicy")
"""On the memory state: the policy individual whose level thresholds apply."""
CREATED = engram("created")
LAST_ACCESSED = engram("lastAccessed")
CONSECUTIVE_WEAK_COUNT = engram("consecutiveWeakCount")
PINNED = engram("pinned")
SIGNATURE_SUBJECT_TYPE = engram("signatureSubjectType")
SIGNATURE_RELATION = engram("signatureRelation")


# --- Autobiographical memory (episodes/) ------------------------------------------
# PROV-O terms reused for episodes, arguments, derivations and ratings.
def prov(name: str) -> NamedNode:
    """The IRI of a PROV-O term by local name: ``prov("Activity")``."""
    return NamedNode(PROV_NS + name)


PROV_ACTIVITY = prov("Activity")
PROV_ENTITY = prov("Entity")
PROV_AGENT = prov("Agent")
PROV_PERSON = prov("Person")
PROV_SOFTWARE_AGENT = prov("SoftwareAgent")
PROV_ASSOCIATION = prov("Association")
PROV_USAGE = prov("Usage")
PROV_ROLE = prov("Role")
PROV_WAS_ASSOCIATED_WITH = prov("wasAssociatedWith")
PROV_QUALIFIED_ASSOCIATION = prov("qualifiedAssociation")
PROV_AGENT_PROPERTY = prov("agent")
PROV_USED = prov("used")
PROV_QUALIFIED_USAGE = prov("qualifiedUsage")
PROV_ENTITY_PROPERTY = prov("entity")
PROV_HAD_ROLE = prov("hadRole")
PROV_WAS_DERIVED_FROM = prov("wasDerivedFrom")
PROV_WAS_GENERATED_BY = prov("wasGeneratedBy")
PROV_GENERATED = prov("generated")
PROV_WAS_ATTRIBUTED_TO = prov("wasAttributedTo")
PROV_STARTED_AT_TIME = prov("startedAtTime")
PROV_ENDED_AT_TIME = prov("endedAtTime")
PROV_GENERATED_AT_TIME = prov("generatedAtTime")
XSD_STRING = NamedNode(XSD_NS + "string")
XSD_INTEGER = NamedNode(XSD_NS + "integer")
XSD_DOUBLE = NamedNode(XSD_NS + "double")
XSD_BOOLEAN = NamedNode(XSD_NS + "boolean")

# Engram's episode terms (engram.ttl, section "Autobiographical memory").
EPISODE = engram("Episode")
ANNOTATION = engram("Annotation")
MEMORY_SNAPSHOT = engram("MemorySnapshot")
SNAPSHOT_CLASS_ENTRY = engram("SnapshotClassEntry")
STREAM_DESCRIPTOR = engram("StreamDescriptor")
FRAME = engram("Frame")
AUGMENTATION_RUN = engram("AugmentationRun")
DERIVED_SAMPLE = engram("DerivedSample")
RATING = engram("Rating")
ACTIVITY_NAME = engram("activityName")
ACTIVITY_TYPE = engram("activityType")
STATE_AT_BEGIN = engram("stateAtBegin")
STATE_AT_END = engram("stateAtEnd")
LEARNED_CLASS_COUNT = engram("learnedClassCount")
EPISODIC_ITEM_COUNT = engram("episodicItemCount")
HAS_CLASS_ENTRY = engram("hasClassEntry")
ENTRY_CLASS = engram("entryClass")
ENTRY_SCORE = engram("entryScore")
ENTRY_RANK = engram("entryRank")
HAPPENED_DURING = engram("happenedDuring")
"""On an episodic scene item (in the ``episodic`` graph): the episode it was perceived in."""
ANNOTATES = engram("annotates")
ANNOTATION_KEY = engram("annotationKey")
ANNOTATION_VALUE = engram("annotationValue")
CONFIDENCE = engram("confidence")
RANGE_START = engram("rangeStart")
RANGE_END = engram("rangeEnd")
STREAM_PROVIDER = engram("provider")
STREAM_CHANNEL = engram("channel")
MESSAGE_TYPE = engram("messageType")
SAMPLE_COUNT = engram("sampleCount")
DROPPED_COUNT = engram("droppedCount")
FIRST_SAMPLE_TIME = engram("firstSampleTime")
LAST_SAMPLE_TIME = engram("lastSampleTime")
STREAM_FILE = engram("streamFile")
FRAME_OF = engram("frameOf")
FRAME_NUMBER = engram("frameNumber")
AUGMENTS = engram("augments")
AUGMENTATION_NAME = engram("augmentationName")
RUN_VERSION = engram("runVersion")
PARAMETERS = engram("parameters")
SOURCE_CHANNEL = engram("sourceChannel")
DERIVED_CHANNEL = engram("derivedChannel")
RATES = engram("rates")
RATING_VALUE = engram("ratingValue")
RATING_QUESTION = engram("ratingQuestion")
"""On a rating: the question it answers (several questions per rated item)."""
QUESTION_NS = BASE + "question/"
ARGUMENT_CONFIDENCE = engram("argumentConfidence")
"""On an argument (association or usage) asserted after the fact: how sure its author is."""
RETRACTED_BY = engram("retractedBy")
"""On an argument no longer held: the agent that removed or replaced it."""
SCENE_AT_TIME = engram("sceneAtTime")
"""On a memory snapshot of an episode: the scene memory's current scene (last stored) then."""
PARTICIPANT_AT_TIME = engram("participantAtTime")
"""On a memory snapshot of an episode: a participant in one of its arguments then."""
PROV_WAS_REVISION_OF = prov("wasRevisionOf")
PROV_INVALIDATED_AT_TIME = prov("invalidatedAtTime")
EPISODE_NS = BASE + "episode/"
"""Episode IRIs are ``<EPISODE_NS><id>``; their parts (snapshots, frames, runs) extend them."""
PARTICIPANT_NS = BASE + "participant/"
"""Named participants of episodes (people, modules, objects): ``<PARTICIPANT_NS><name>``."""
ROLE_NS = BASE + "role/"

# --- ARMOR directive API (api/armor): the reference registry ------------------------------------
ARMOR_NS = BASE + "armor#"
ARMOR_REGISTRY = NamedNode(GRAPH_NS + "armor")
"""Graph holding one node per loaded ARMOR reference and its settings (prefix, flags, source)."""
ARMOR_REFERENCE = NamedNode(ARMOR_NS + "Reference")
ARMOR_NAME = NamedNode(ARMOR_NS + "name")
ARMOR_PREFIX = NamedNode(ARMOR_NS + "prefix")
ARMOR_BUFFERED_MANIPULATION = NamedNode(ARMOR_NS + "bufferedManipulation")
ARMOR_BUFFERED_REASONER = NamedNode(ARMOR_NS + "bufferedReasoner")
ARMOR_REASONER = NamedNode(ARMOR_NS + "reasoner")
ARMOR_SOURCE = NamedNode(ARMOR_NS + "source")
ARMOR_SOURCE_FORMAT = NamedNode(ARMOR_NS + "sourceFormat")
OWL_THING = NamedNode(OWL_NS + "Thing")
OWL_NOTHING = NamedNode(OWL_NS + "Nothing")

# --- Scene memory (reasoners/) ----------------------------------------------------
EXPERIENCED_SCENE = engram("ExperiencedScene")
MEMORY_STATE = engram("MemoryState")
MEMORY_STATE_INDIVIDUAL = engram("memoryState")
"""The one MemoryState individual, in the ``memory`` graph."""
HAS_PRIMITIVE = engram("hasPrimitive")
FORGOTTEN_AT = engram("forgottenAt")
FORGOTTEN_SIGNATURE = engram("forgottenSignature")
LAST_SLEEP_AT = engram("lastSleepAt")
UPDATES_SINCE_SLEEP = engram("updatesSinceSleep")
SLEEP_PASS_COUNT = engram("sleepPassCount")
CENTRE = (engram("centreX"), engram("centreY"), engram("centreZ"))
AXIS = (engram("axisX"), engram("axisY"), engram("axisZ"))
APEX = (engram("apexX"), engram("apexY"), engram("apexZ"))
POINT_ON_AXIS = (engram("pointOnAxisX"), engram("pointOnAxisY"), engram("pointOnAxisZ"))
COLOUR = (engram("colourR"), engram("colourG"), engram("colourB"))
RADIUS = engram("radius")
HEIGHT = engram("height")
HESSIAN_OFFSET = engram("hessianOffset")
EXTENT = (engram("extentX"), engram("extentY"))
"""A plane's extent: the sides of its points' bounding rectangle along the scene's x and y."""
TRACKING_ID = engram("trackingId")
OBSERVED_AT = engram("observedAt")
IS_RIGHT_OF = engram("isRightOf")
IS_BEHIND_OF = engram("isBehindOf")
IS_ABOVE_OF = engram("isAboveOf")
IS_PARALLEL_WITH = engram("isParallelWith")
IS_PERPENDICULAR_WITH = engram("isPerpendicularWith")
IS_COAXIAL_WITH = engram("isCoaxialWith")
IS_ALONG_X_WITH = engram("isAlongXWith")
IS_ALONG_Y_WITH = engram("isAlongYWith")
IS_ALONG_Z_WITH = engram("isAlongZWith")

# --- Bulk writes (kg.Store.fill_graph: REASON's closure) --------------------------------------
BULK_WRITES = NamedNode(GRAPH_NS + "bulk-writes")
"""Markers of bulk writes in progress: a graph named here may be half-written (see
``kg.Store.fill_graph``); opening the store clears it (``kg.Store.recover_bulk_writes``)."""
UNFINISHED_BULK_WRITE = engram("UnfinishedBulkWrite")

# --- A memory on a shared SPARQL server (kg.remote) --------------------------------
MEMORY_NS = BASE + "memory/"
"""Each robot's memory on a shared server lives under ``MEMORY_NS + <name> + "/"``: its graphs
under ``.../graph/``, its revision, journal and writer's lease in ``.../control``."""
REVISION = engram("revision")
"""On a memory node: how many transactions have been committed to it; on a journal entry: the
revision that transaction made."""
JOURNAL_ENTRY = engram("JournalEntry")
TOUCHED = engram("touched")
"""On a journal entry: a subject whose triples the transaction changed."""
TOUCHED_EVERYTHING = engram("touchedEverything")
"""On a journal entry: the transaction changed too much to list (a cleared graph, a sleep pass):
followers rebuild everything."""
COMMITTED_AT = engram("committedAt")
LEASE_HOLDER = engram("leaseHolder")
LEASE_EXPIRES = engram("leaseExpires")

# --- Recordings on object storage (episodes.archive) -------------------------------
STREAM_OBJECT = engram("streamObject")
"""On an episode and on its stream descriptors: an ``s3://`` object holding its recording."""
BYTE_SIZE = engram("byteSize")
SHA256 = engram("sha256")
"""On a stored object: the hex SHA-256 of its bytes."""

# --- Scene memory revision (reasoners.index_file: opening fast) ---------------------
MEMORY_REVISION_GRAPH = NamedNode(GRAPH_NS + "memory-revision")
"""Holds one triple, ``engram:memoryState engram:revision "<token>"``, replaced by every committed
scene-memory transaction: the index file saved beside the store names the revision it mirrors.
Not exported (not part of the ontology)."""
MEMORY_REVISION = REVISION

# --- Scene memory history (reasoners.history) ---------------------------------------
HISTORY_NS = BASE + "history/"
"""Event IRIs are ``<HISTORY_NS><UTC time in ms, 13 digits>-<sequence, 19 digits>``: sorted as
strings, they are in the order the events happened."""
MEMORY_EVENT = engram("MemoryEvent")
EVENT_CLASS = engram("eventClass")
"""On a memory event: the learned class it is about."""
EVENT_SCENE = engram("eventScene")
"""On a memory event: the experienced scene it is about."""
EVENT_KIND = engram("eventKind")
EVENT_SCORE = engram("eventScore")
EVENT_LEVEL = engram("eventLevel")
EVENT_STATE = engram("eventState")
"""On an event about a class, in histories written before checkpoints: "<kind> <level or ->
<score or -> <class IRI>" (now a journal entry, :data:`HISTORY_ENTRY`)."""
HISTORY_PASS_EVENTS = engram("historyPassEvents")
"""On an epoch node of the history: one sleep pass's class events (its level changes and
periodic re-scorings) as plain text that SPARQL string functions read: a first line "<event IRI
after HISTORY_NS> <time, xsd:dateTime lexical form>", then one line per event "<class IRI>
<kind> <level> <score>", every line ending with a line feed."""
HISTORY_PASS_ENTRIES = engram("historyPassEntries")
"""In histories written before :data:`HISTORY_PASS_EVENTS`: a pass's events as
:data:`HISTORY_ENTRY` lines, zlib + base64 (read as they are; the memory rewrites them as
:data:`HISTORY_PASS_EVENTS` when it opens, :mod:`reasoners.migration`)."""
HISTORY_ENTRY = engram("historyEntry")
"""On an epoch node of the history (``<HISTORY_NS>epoch-<k>``): one class event written in epoch
k, "<event IRI after HISTORY_NS> <kind> <level or -> <score or -> <class IRI>"."""
CHECKPOINT_SUMMARY = engram("checkpointSummary")
"""On a history checkpoint (``<HISTORY_NS>checkpoint-<k>``): "<k> <largest event covered>
<smallest event of epoch k-1>" (event IRIs after HISTORY_NS; ~ for none)."""
CHECKPOINT_STATE = engram("checkpointState")
"""On a history checkpoint: each class's last event covered, as journal entries, zlib + base64."""
EVENT_CONFIDENCE = engram("eventConfidence")
"""On a learned or reinforced event: the confidence of the best class the scene belonged to."""
EVENT_BEST_MATCH = engram("eventBestMatch")
"""On a learned event: the best class the scene belonged to, then (a reinforced class is it)."""
EVENT_PARENT = engram("eventParent")
"""On a learned event written before :data:`EVENT_PARENTS`: a direct parent the new class was
placed under (one triple each)."""
EVENT_PARENTS = engram("eventParents")
"""On a learned event: the direct parents the new class was placed under, their IRIs separated
by spaces in one literal ("" for none)."""
PROV_AT_TIME = prov("atTime")
