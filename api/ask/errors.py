"""The errors of asking the memory.

EngramError (kg)
└── SpeechUnavailableError   espeak-ng or pocketsphinx is missing (UnavailableError, HTTP 503)

Bad questions and bad audio raise ``kg.errors.InvalidValueError`` (HTTP 422), naming the
field, the value and what was expected.
"""

from kg.errors import UnavailableError

__all__ = ["SpeechUnavailableError"]


class SpeechUnavailableError(UnavailableError):
    """espeak-ng or pocketsphinx is not installed."""
