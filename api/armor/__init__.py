"""ARMOR's directive protocol over HTTP, on Engram's store.

Robot software written for ARMOR (the ROS multi-ontology reference) talks to Engram with no
change but the transport: the request and response fields, the command table, names, literal
types, output strings, exit codes, mount and buffering follow ``armor-protocol.md``. Where ARMOR's
Java code is buggy, Engram implements the documented intent:

- the mount lock is enforced: a manipulation by another client than the mounted one answers 102;
- the list service executes every directive in order and answers each;
- a reference that was never loaded answers its own code, 207, not a null-pointer 205;
- errors ARMOR let crash the ROS call (too few args, a bad number, an unknown reasoner, an
  unreadable file) answer ``success=false`` with 208 or 209 and a message naming the argument;
- SAVE INFERENCE writes the inferences to the file without asserting them in the reference.

**Transactions (an Engram extension).** ARMOR applies each directive of a list as it goes, so a
failure in the middle leaves the earlier ones applied. Here a directive list is one transaction:
every directive still runs in order and gets its own response, but the writes are committed
together at the end, and only if no directive failed (``success=false`` with a non-zero exit
code). Otherwise none of the list's writes stays, and the list answers ``success=false``. A
single directive is a list of one. A ``QUERY IND`` that finds nothing answers ``success=false``
with exit code 0, as in ARMOR; that is an answer, not a failure, and does not undo the list.
Directives of a list see the writes of the earlier directives of the same list; other clients
see them only once the list committed. ``is_consistent`` of every response is the reference's
consistency when its list ended.

**Concurrency.** Any number of clients may send directives at once. Lists that write a
reference hold that reference's lock (taken in name order, so lists never deadlock) from their
first directive to their commit; queries take no lock and see committed states only.

Exit codes: see :mod:`api.armor.errors`. The request and response models are
:mod:`api.protocol`'s, shared with the robot-side client.
"""

from api.armor.engine import COMMANDS, ArmorEngine, directive_key

__all__ = [
    "COMMANDS",
    "ArmorEngine",
    "directive_key",
]
