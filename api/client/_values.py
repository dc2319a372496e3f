"""The ARMOR answers' strings as Python values: IRIs as names, numbers as numbers.

ARMOR answers every value as a string (``"<https://w3id.org/engram/ontology#Scene-2>"``,
``"0.5"``, ``"\\"3\\"^^xsd:integer"``, ``"<...#Scene-1> 0.87"``); :func:`parse_value` reads one.

>>> parse_value("<https://w3id.org/engram/ontology#Scene-2>")
'Scene-2'
>>> parse_value("0.5"), parse_value("4"), parse_value("true")
(0.5, 4, True)
>>> parse_value('"3"^^xsd:integer'), parse_value('"blue"')
(3, 'blue')
>>> parse_value("<https://w3id.org/engram/ontology#Scene-1> 0.87")
('Scene-1', 0.87)
"""

import re

__all__ = ["Value", "parse_value"]

Value = str | int | float | bool | None | tuple["Value", ...]
"""A value of an answer: a name, a number, a truth value, text, or several of them."""

_IRI = re.compile(r"<([^>]*)>")
_TYPED = re.compile(r'^"(.*)"(?:\^\^(\S+)|@[A-Za-z-]+)?$', re.DOTALL)
_INTEGER = re.compile(r"[+-]?\d+")
_DECIMAL = re.compile(r"[+-]?(\d+\.?\d*|\.\d+)([eE][+-]?\d+)?")
_NUMBER_TYPES = ("integer", "int", "long", "short", "double", "float", "decimal")


def _name(iri: str) -> str:
    """The local name of an IRI: after its ``#``, else after its last ``/``."""
    return re.split(r"[#/]", iri.rstrip("/#"))[-1] or iri


def _token(text: str) -> Value:
    if text.startswith("<") and text.endswith(">"):
        return _name(text[1:-1])
    typed = _TYPED.match(text)
    if typed:
        lexical, datatype = typed.group(1), (typed.group(2) or "").strip("<>")
        if datatype.endswith("boolean"):
            return lexical == "true"
        if re.split(r"[:#]", datatype)[-1] in _NUMBER_TYPES:
            return _number(lexical) if _number(lexical) is not None else lexical
        return lexical
    if text in ("true", "false"):
        return text == "true"
    number = _number(text)
    return number if number is not None else text


def _number(text: str) -> int | float | None:
    if _INTEGER.fullmatch(text):
        return int(text)
    return float(text) if _DECIMAL.fullmatch(text) else None


def parse_value(text: str) -> Value:
    """One ARMOR answer string as a value; a string of several IRIs or numbers separated by
    spaces (``"<class> 0.87"``) as a tuple of them. An empty string is ``None``."""
    text = text.strip()
    if not text:
        return None
    if text.startswith('"'):
        return _token(text)
    parts = text.split()
    if len(parts) > 1 and all(_IRI.fullmatch(p) or _number(p) is not None for p in parts):
        return tuple(_token(p) for p in parts)
    return _token(text)
