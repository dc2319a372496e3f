"""The cue index: keys on each still-valid argument that let a cue find its episodes in one
index lookup instead of joining every episode of the activity with every argument.

An argument (a qualified association or usage of an episode) that holds participant ``who`` in
``role`` of an episode of ``activity`` carries three ``engram:cueKey`` literals: for the role
and the participant, for the participant in any role, and for anyone in the role. A cue with
``agent=HyungJin`` on ``pointing`` looks up the one key ``"<role/agent> <participant/HyungJin>
pointing"``. The keys are written with the argument (:mod:`episodes.lifecycle`,
:mod:`episodes.arguments`) and deleted when it is retracted, in the same transaction, so cues
see a change at once; :func:`backfill` adds the keys to arguments stored before the index
existed. The PROV triples stay the source of truth: an analyst's query over
``prov:qualifiedAssociation`` / ``prov:hadRole`` answers the same.

>>> from pyoxigraph import NamedNode
>>> cue_key("pointing", NamedNode("https://w3id.org/engram/role/agent"), None).value
'https://w3id.org/engram/role/agent * pointing'
"""

from pyoxigraph import Literal, NamedNode

from episodes import _rdf
from kg import Store, Transaction
from ontologies.vocab import EPISODES, engram

__all__ = ["CUE_KEY", "backfill", "cue_key", "cue_keys", "drop_keys", "write_keys"]

CUE_KEY = engram("cueKey")
ANY = "*"


def cue_key(activity: str, role: NamedNode | None, who: NamedNode | None) -> Literal:
    """The key of "``who`` in ``role`` of an episode of ``activity``"; ``None`` is "any".

    IRIs hold no spaces, so the role and participant IRIs (or ``*``) come first and the
    activity name, which may, last: the key is unambiguous.
    """
    role_part = role.value if role is not None else ANY
    who_part = who.value if who is not None else ANY
    return Literal(f"{role_part} {who_part} {activity}")


def cue_keys(activity: str, role: NamedNode, who: NamedNode) -> tuple[Literal, ...]:
    """The three keys an argument carries: role and participant, participant, role."""
    return (
        cue_key(activity, role, who),
        cue_key(activity, None, who),
        cue_key(activity, role, None),
    )


def write_keys(
    tx: Transaction, link: NamedNode, activity: str, role: NamedNode, who: NamedNode
) -> None:
    """Index the argument ``link`` (``who`` in ``role`` of an episode of ``activity``)."""
    for key in cue_keys(activity, role, who):
        tx.insert(link, CUE_KEY, key, EPISODES)


def drop_keys(
    tx: Transaction, link: NamedNode, activity: str, role: NamedNode, who: NamedNode
) -> None:
    """Take a retracted argument out of the index."""
    for key in cue_keys(activity, role, who):
        tx.delete(link, CUE_KEY, key, EPISODES)


def backfill(store: Store) -> int:
    """Index the valid arguments that lack their keys (stored before the index); how many."""
    rows = store.select("episodes_cue_unindexed")
    if not rows:
        return 0
    with store.transaction() as tx:
        for row in rows:
            write_keys(
                tx,
                _rdf.iri(row, "link"),
                _rdf.text(row, "activity"),
                _rdf.iri(row, "role"),
                _rdf.iri(row, "who"),
            )
    return len(rows)
