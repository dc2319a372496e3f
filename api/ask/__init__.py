"""Asking the memory in words and in speech.

- :mod:`api.ask.grammar`: the question forms (patterns over words, no language model), the same
  forms as JSGF for the recogniser, and the closest forms to a question outside them;
- :mod:`api.ask.vocabulary`: objects, relations, times, numbers and the episodes' names;
- :mod:`api.ask.asker`: :class:`Asker` answers in words, as JSON, with the explanations
  (:mod:`reasoners.explain`) and the SPARQL behind the answer;
- :mod:`api.ask.speech`: offline speech: pocketsphinx constrained by the grammar, espeak-ng.
"""

from api.ask.asker import Answer, Asker
from api.ask.grammar import FORMS, closest, parse

__all__ = ["FORMS", "Answer", "Asker", "closest", "parse"]
