"""Python's cyclic garbage collector paused around work that allocates millions of objects.

A REASON, reading or saving the memory's index file, and a sleep pass at 100,000 classes each
build a few million objects that either stay alive or die by reference counting, not in cycles.
Each collector pass the allocations set off walks the whole heap (the memory model included),
over and over: a fifth of a REASON's time at 50k triples, a third of reading an index file at
30,000 classes, about 2.4 of the 9.4-9.9 s of Python in a sleep pass at 100,000 classes (one
memory's copies, the pass timed with and without the pause). Pausing it is safe: nothing is left
behind that only the collector could free, and it runs again as soon as the work ends.
"""

import contextlib
import gc
from collections.abc import Iterator

__all__ = ["collector_paused"]


@contextlib.contextmanager
def collector_paused(*, age_survivors: bool = False) -> Iterator[None]:
    """Pause the collector for the ``with`` block (nesting is fine; the outermost resumes it).

    With ``age_survivors``, what the block built and kept is handed to the oldest generation
    directly (``gc.freeze`` then ``gc.unfreeze``), so that the first collections after it do not
    walk it again as young objects (0.3-0.4 s after reading an index file of 100,000 classes).
    It stays collectable: the next full collection sees it, as it would have."""
    was_enabled = gc.isenabled()
    gc.disable()
    try:
        yield
    finally:
        if age_survivors:
            gc.freeze()
            gc.unfreeze()
        if was_enabled:
            gc.enable()
