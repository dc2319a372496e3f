"""One episode's triples in and out, as TriG (the ``episodes`` graph, and the scene links in
the ``episodic`` graph). With the stream files (``GET /episodes/{id}/streams/export``) this
moves a whole episode from one memory to another.
"""

from pyoxigraph import NamedNode, Quad, RdfFormat, parse, serialize

from episodes import _rdf
from episodes.errors import EpisodeStateError, InvalidInputError
from episodes.lifecycle import episode_times, require_episode
from episodes.terms import episode_id_of, episode_iri
from kg import Store
from ontologies.vocab import (
    EPISODE,
    EPISODE_NS,
    EPISODES,
    EPISODIC,
    HAPPENED_DURING,
    PARTICIPANT_NS,
    PREFIXES,
    RDF_TYPE,
    ROLE_NS,
)

__all__ = ["export_episode", "import_episode"]

_REFERENCES = ("agent", "entity", "hadRole", "wasAttributedTo", "wasAssociatedWith")


def export_episode(store: Store, episode_id: str) -> bytes:
    """The episode's quads as TriG: its nodes and parts, the participants and roles they
    name, and the scene links. Raises :class:`EpisodeNotFoundError`."""
    episode, _, _ = require_episode(store, episode_id)
    nodes = [_rdf.iri(r, "node") for r in store.select("episodes_owned_nodes", episode=episode)]
    quads: list[Quad] = []
    named: set[NamedNode] = set()
    for node in nodes:
        for quad in store.quads(node, None, None, EPISODES):
            quads.append(quad)
            if quad.predicate.value.rsplit("#", 1)[-1] in _REFERENCES and isinstance(
                quad.object, NamedNode
            ):
                named.add(quad.object)
    for node in sorted(named, key=str):
        quads.extend(store.quads(node, None, None, EPISODES))
    quads.extend(store.quads(None, HAPPENED_DURING, episode, EPISODIC))
    return serialize(quads, format=RdfFormat.TRIG, prefixes=dict(PREFIXES)) or b""


def import_episode(store: Store, data: bytes) -> str:
    """Load an episode exported by :func:`export_episode`; return its id.

    Raises :class:`InvalidInputError` if the document does not parse or is not one episode's
    export (one episode; only its parts, participants and roles; only the two graphs), and
    :class:`EpisodeStateError` if the memory already holds that episode. Nothing is written
    then.
    """
    try:
        quads = list(parse(data, format=RdfFormat.TRIG))
    except SyntaxError as error:
        raise InvalidInputError("body", f"{len(data)} bytes", f"TriG ({error})") from None
    episodes = {q.subject for q in quads if q.predicate == RDF_TYPE and q.object == EPISODE}
    if len(episodes) != 1:
        raise InvalidInputError("body", f"{len(episodes)} episodes", "exactly one engram:Episode")
    (episode,) = episodes
    if not isinstance(episode, NamedNode) or not episode.value.startswith(EPISODE_NS):
        raise InvalidInputError("body", str(episode), f"an episode IRI under {EPISODE_NS}")
    episode_id = episode_id_of(episode)
    own = episode.value + "/"
    for quad in quads:
        subject = quad.subject.value if isinstance(quad.subject, NamedNode) else ""
        if quad.graph_name == EPISODIC:
            if quad.predicate != HAPPENED_DURING or quad.object != episode:
                raise InvalidInputError("body", str(quad), "only scene links to the episode")
        elif quad.graph_name != EPISODES:
            raise InvalidInputError("body", str(quad.graph_name), "the episodes graph")
        elif not (subject == episode.value or subject.startswith((own, PARTICIPANT_NS, ROLE_NS))):
            raise InvalidInputError("body", subject, "the episode, its parts, participants, roles")
    with store.transaction() as tx:
        if episode_times(store, episode_iri(episode_id)) is not None:
            raise EpisodeStateError(f"id: an episode {episode_id!r} already exists")
        for quad in quads:
            tx.insert(quad.subject, quad.predicate, quad.object, quad.graph_name)
    return episode_id
