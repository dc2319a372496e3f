"""``bench/perception_seeds.py`` matches primitives to measured objects as ``bench/perception.py``
does: one matcher, so that a seed's line and the bench's row never disagree about an object
(before stop 40's end it kept its own, which counted a primitive for every object within 8 cm)."""

import json

from shapes import Perception, PerceptionParams, open_source
from tests.shapes.real_scans import SCANS, bench_module

TRUTH = json.loads((SCANS / "truth.json").read_text())


def test_a_seed_line_is_the_bench_row() -> None:
    seeds, bench = bench_module("perception_seeds"), bench_module("perception")
    frame = next(open_source(SCANS / "mug_stereo.npz"))
    result = Perception(PerceptionParams(gravity_from_scene=True), seed=0).process(frame)
    cells, tally = bench._objects_row(result, TRUTH["mug_stereo"])
    assert seeds.row("mug_stereo", TRUTH["mug_stereo"], 0) == (
        f"{'; '.join(cells)} | others {tally['strays']}"
    )
    assert cells[0].startswith("mug 1, ")
