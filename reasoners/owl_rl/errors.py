"""The exceptions of the OWL 2 RL reasoner.

ReasonerError
├── UnknownReasonerError    the reasoner name is not an accepted alias (a ValueError too)
└── SwrlRuleError           a SWRL rule is malformed or unsupported (a ValueError too)
"""

__all__ = ["ReasonerError", "SwrlRuleError", "UnknownReasonerError"]


class ReasonerError(Exception):
    """Base of every error the OWL 2 RL reasoner raises on purpose."""


class UnknownReasonerError(ReasonerError, ValueError):
    """The reasoner name is not one Engram accepts."""


class SwrlRuleError(ReasonerError, ValueError):
    """A SWRL rule cannot be used: malformed, not DL-safe, or an unsupported built-in."""
