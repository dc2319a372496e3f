"""Sample data shipped with the package, for a first ``engram perceive``.

``BREAKFAST`` is one synthetic depth frame of the demo's breakfast scene (a yellow ball left
of a blue can, on a table) as a binary PLY of 16,000 coloured points in the world frame, in
metres (z up)::

    engram perceive "$(python -c 'from api.samples import BREAKFAST; print(BREAKFAST)')" --local
"""

from pathlib import Path

__all__ = ["BREAKFAST"]

BREAKFAST = Path(__file__).with_name("breakfast.ply")
