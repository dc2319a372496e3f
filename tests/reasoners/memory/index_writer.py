"""A process that fills a scene memory on disk and is killed while it saves the index file.

Run as ``python -m tests.reasoners.memory.index_writer STORE_DIR MODE``: it stores scenes,
saves the index file (complete, at that revision), stores one more scene, then saves again and
stops inside that save, printing ``SAVING`` so that the test can SIGKILL it there:

- ``mid-write``: half of the new file's bytes are written to the temporary file;
- ``before-rename``: the temporary file is written and fsynced, not yet renamed.
"""

import datetime as dt
import os
import sys
import time
from pathlib import Path
from typing import Any

from kg import Store
from kg.primitive import Primitive
from reasoners import index_file
from reasoners.memory import SceneMemory

START = dt.datetime(2025, 3, 1, 9, 0, tzinfo=dt.UTC)


def scenes() -> list[list[Primitive]]:
    """Ten scenes that learn classes with subclass edges between them."""
    out = []
    for k in range(10):
        objects = [Primitive("table", "Plane", centre=(0.3, 0.1, 0.0), axis=(0, 0, 1))]
        for j in range(1 + k % 4):
            objects.append(
                Primitive(f"s{j}", "Sphere", centre=(0.1 * j, 0.3 + 0.1 * k, 0.3), radius=0.04)
            )
        out.append(objects)
    return out


def _stop(message: str = "SAVING") -> None:
    print(message, flush=True)
    time.sleep(600)


class _HalfWriter:
    """A file that writes half of what it is given, then stops the process in place."""

    def __init__(self, file: Any) -> None:
        self.file = file

    def __enter__(self) -> "_HalfWriter":
        return self

    def __exit__(self, *exc: object) -> None:
        self.file.close()

    def write(self, data: bytes) -> int:
        if len(data) > 100:  # the payload (the header is written first, whole)
            self.file.write(data[: len(data) // 2])
            self.file.flush()
            os.fsync(self.file.fileno())
            _stop()
        return int(self.file.write(data))


def main() -> None:
    directory, mode = Path(sys.argv[1]), sys.argv[2]
    memory = SceneMemory(Store(directory), clock=lambda: START)
    *first, last = scenes()
    for scene in first:
        memory.store_scene(scene)
    memory.retrieve([("Sphere", "isAboveOf", "Plane")])
    assert memory.save_index()
    memory.store_scene(last)
    if mode == "mid-write":
        index_file.open = lambda path, how: _HalfWriter(open(path, how))  # type: ignore[attr-defined]  # noqa: SIM115
    elif mode == "before-rename":
        os.replace = lambda *args, **kwargs: _stop()  # type: ignore[assignment]
    else:
        raise SystemExit(f"mode: got {mode!r}, expected mid-write or before-rename")
    memory.save_index()
    raise SystemExit("the save returned; expected to be killed inside it")


if __name__ == "__main__":
    main()
