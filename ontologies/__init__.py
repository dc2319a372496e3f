"""The Engram T-Box (Turtle files) and the vocabulary constants that name its terms."""

from importlib.resources import files
from pathlib import Path

__all__ = ["ENGRAM_TTL"]

ENGRAM_TTL: Path = Path(str(files(__name__).joinpath("engram.ttl")))
"""Path of the Engram ontology in Turtle."""
