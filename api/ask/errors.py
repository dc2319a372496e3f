"""The errors of asking the memory.

EngramError (kg)
└── SpeechUnavailableError   espeak-ng or pocketsphinx is missing (HTTP 503)

Bad questions and bad audio raise ``episodes.errors.InvalidInputError`` (HTTP 422), naming the
field, the value and what was expected.
"""

from kg.errors import EngramError

__all__ = ["SpeechUnavailableError"]


class SpeechUnavailableError(EngramError):
    """espeak-ng or pocketsphinx is not installed."""
