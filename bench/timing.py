"""What the bench scripts print beside their figures: the machine's load, and a median timer.

Imported as ``bench.timing`` by a script run from the repository root (each puts the root on
``sys.path``). A loopback port for a server is :func:`tests.conftest.free_port`.
"""

import os
import statistics
import time
from collections.abc import Callable


def load_average() -> str:
    """The 1, 5 and 15 minute load averages and the CPU count, as one phrase."""
    one, five, fifteen = os.getloadavg()
    return f"load average {one:.2f} {five:.2f} {fifteen:.2f} on {os.cpu_count()} CPUs"


def median_s(
    call: Callable[[], object], repeat: int, *, clock: Callable[[], float] = time.perf_counter
) -> float:
    """Median seconds of ``repeat`` calls of ``call`` on ``clock``: wall-clock time by default;
    ``time.thread_time`` or ``time.process_time`` for CPU time, which waiting for a core on a
    loaded machine does not inflate."""
    samples = []
    for _ in range(repeat):
        began = clock()
        call()
        samples.append(clock() - began)
    return statistics.median(samples)
