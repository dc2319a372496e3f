"""The exceptions of the OWL 2 RL reasoner.

EngramError (kg)
└── ReasonerError
    ├── UnknownReasonerError    the reasoner name is not an accepted alias (InvalidInputError)
    └── SwrlRuleError           a SWRL rule is malformed or unsupported (InvalidInputError)
"""

from kg.errors import EngramError, InvalidInputError

__all__ = ["ReasonerError", "SwrlRuleError", "UnknownReasonerError"]


class ReasonerError(EngramError):
    """Base of every error the OWL 2 RL reasoner raises on purpose."""


class UnknownReasonerError(ReasonerError, InvalidInputError):
    """The reasoner name is not one Engram accepts."""


class SwrlRuleError(ReasonerError, InvalidInputError):
    """A SWRL rule cannot be used: malformed, not DL-safe, or an unsupported built-in."""
