"""The OWL 2 RL datatypes: which literals belong to which, and which literals are equal.

This is the datatype map the rules dt-type1, dt-type2, dt-eq, dt-diff and dt-not-type read
(OWL 2 Profiles, section 4.3, table 8). A literal belongs to a datatype when its data value is in
the datatype's value space: ``"5"^^xsd:integer`` is also an ``xsd:byte`` and an
``xsd:nonNegativeInteger``, ``"a"`` is an ``xsd:string`` and an ``rdf:PlainLiteral``. Terms are
N-Triples text, as in the engine.

>>> sorted(t.split("#")[1][:-1] for t in value_types('"5"^^<http://www.w3.org/2001/XMLSchema#byte>'))[:4]
['Literal', 'byte', 'decimal', 'int']
>>> is_valid('"300"^^<http://www.w3.org/2001/XMLSchema#byte>')
False
>>> value_key('"5.0"^^<http://www.w3.org/2001/XMLSchema#decimal>') == value_key(
...     '"5"^^<http://www.w3.org/2001/XMLSchema#long>')
True
"""

import math
import re
from datetime import datetime
from fractions import Fraction
from functools import lru_cache
from xml.etree import ElementTree

from reasoners.owl_rl._terms import rdf, rdfs, unescape, xsd

__all__ = ["RL_DATATYPES", "in_value_space", "is_valid", "value_key", "value_types"]

_BOUNDS: dict[str, tuple[int | None, int | None]] = {
    xsd("integer"): (None, None),
    xsd("long"): (-(2**63), 2**63 - 1),
    xsd("int"): (-(2**31), 2**31 - 1),
    xsd("short"): (-(2**15), 2**15 - 1),
    xsd("byte"): (-(2**7), 2**7 - 1),
    xsd("nonNegativeInteger"): (0, None),
    xsd("positiveInteger"): (1, None),
    xsd("nonPositiveInteger"): (None, 0),
    xsd("negativeInteger"): (None, -1),
    xsd("unsignedLong"): (0, 2**64 - 1),
    xsd("unsignedInt"): (0, 2**32 - 1),
    xsd("unsignedShort"): (0, 2**16 - 1),
    xsd("unsignedByte"): (0, 2**8 - 1),
}
_REALS = (xsd("decimal"),)
_STRINGS = (xsd("string"), rdf("PlainLiteral"))
_STRING_SUBTYPES = {
    xsd("normalizedString"): re.compile(r"[^\r\n\t]*"),
    xsd("token"): re.compile(r"(\S+( \S+)*)?"),
    xsd("language"): re.compile(r"[a-zA-Z]{1,8}(-[a-zA-Z0-9]{1,8})*"),
    xsd("Name"): re.compile(r"[A-Za-z_:][\w.:-]*"),
    xsd("NCName"): re.compile(r"[A-Za-z_][\w.-]*"),
    xsd("NMTOKEN"): re.compile(r"[\w.:-]+"),
}
_LEXICAL = {
    xsd("boolean"): re.compile(r"true|false|1|0"),
    xsd("hexBinary"): re.compile(r"([0-9a-fA-F]{2})*"),
    xsd("base64Binary"): re.compile(r"[A-Za-z0-9+/= ]*"),
    xsd("dateTime"): re.compile(r"-?\d{4,}-\d\d-\d\dT\d\d:\d\d:\d\d(\.\d+)?(Z|[+-]\d\d:\d\d)?"),
    xsd("dateTimeStamp"): re.compile(r"-?\d{4,}-\d\d-\d\dT\d\d:\d\d:\d\d(\.\d+)?(Z|[+-]\d\d:\d\d)"),
    xsd("date"): re.compile(r"-?\d{4,}-\d\d-\d\d(Z|[+-]\d\d:\d\d)?"),
    xsd("time"): re.compile(r"\d\d:\d\d:\d\d(\.\d+)?(Z|[+-]\d\d:\d\d)?"),
}
_OTHER = (xsd("anyURI"), rdf("XMLLiteral"), rdf("HTML"), rdf("langString"))
_LANGUAGE_TAG = re.compile(r"[a-zA-Z]{1,8}(-[a-zA-Z0-9]{1,8})*")
_URI = re.compile(r"([A-Za-z][A-Za-z0-9+.-]*:)?[^\s<>\"{}|\\^`]*")
_INTEGER = re.compile(r"[+-]?\d+")
_DECIMAL = re.compile(r"[+-]?(\d+(\.\d*)?|\.\d+)")
_FLOAT = re.compile(r"[+-]?(\d+(\.\d*)?|\.\d+)([eE][+-]?\d+)?|[+-]?INF|NaN")

RL_DATATYPES = frozenset(
    [
        *_BOUNDS,
        *_REALS,
        *_STRINGS,
        *_STRING_SUBTYPES,
        *_LEXICAL,
        *_OTHER,
        xsd("float"),
        xsd("double"),
        rdfs("Literal"),
    ]
)
"""The datatypes of the OWL 2 RL datatype map: OWL 2's, less ``owl:real`` and ``owl:rational``
(Profiles, section 4.2). dt-type1 types each one ``rdfs:Datatype``."""


def _split(term: str) -> tuple[str, str | None, str | None]:
    """(lexical form, datatype term or None, language or None) of a literal term."""
    end = term.rfind('"')
    lexical, rest = term[1:end], term[end + 1 :]
    if "\\" in lexical:
        lexical = unescape(lexical)
    if rest.startswith("^^"):
        return lexical, rest[2:], None
    if rest.startswith("@"):
        return lexical, None, rest[1:].lower()
    return lexical, xsd("string"), None


@lru_cache(maxsize=65_536)
def _value(term: str) -> tuple[str, object] | None:
    """(value space, value) of a literal of the datatype map; None if ill-typed or unknown."""
    lexical, datatype, language = _split(term)
    if language is not None:
        return ("lang", (lexical, language))
    if datatype in _BOUNDS:
        if not _INTEGER.fullmatch(lexical):
            return None
        number = int(lexical)
        low, high = _BOUNDS[datatype]
        if (low is not None and number < low) or (high is not None and number > high):
            return None
        return ("real", Fraction(number))
    if datatype == xsd("decimal"):
        return ("real", Fraction(lexical)) if _DECIMAL.fullmatch(lexical) else None
    if datatype in (xsd("double"), xsd("float")):
        return _floating(lexical, datatype == xsd("float"))
    if datatype == rdf("PlainLiteral"):
        text, at, tag = lexical.rpartition("@")
        if not at or (tag and not _LANGUAGE_TAG.fullmatch(tag)):
            return None
        return ("lang", (text, tag.lower())) if tag else ("string", text)
    if datatype == xsd("anyURI"):
        return (datatype, lexical) if _is_uri(lexical) else None
    if datatype == rdf("XMLLiteral"):
        try:
            ElementTree.fromstring(f"<r>{lexical}</r>")
        except ElementTree.ParseError:
            return None
        return (datatype, lexical)
    if datatype in (xsd("dateTime"), xsd("dateTimeStamp")):
        if not _LEXICAL[datatype].fullmatch(lexical):
            return None
        return ("dateTime", _instant(lexical))
    if datatype in _STRINGS or datatype in _STRING_SUBTYPES:
        pattern = _STRING_SUBTYPES.get(datatype or "")
        if pattern is not None and not pattern.fullmatch(lexical):
            return None
        return ("string", lexical)
    if datatype == xsd("boolean"):
        return (
            ("boolean", lexical in ("true", "1")) if _LEXICAL[datatype].fullmatch(lexical) else None
        )
    if datatype in _LEXICAL:
        return (datatype, lexical) if _LEXICAL[datatype].fullmatch(lexical) else None
    if datatype in _OTHER:
        return (datatype, lexical)
    return None


def _floating(lexical: str, single: bool) -> tuple[str, object] | None:
    """An xsd:double or xsd:float value; None when malformed or out of the type's range."""
    if not _FLOAT.fullmatch(lexical):
        return None
    space = "float" if single else "double"
    if lexical == "NaN":
        return (space, "NaN")  # OWL 2: equality is identity, so NaN is equal to itself
    number = float(lexical.replace("INF", "inf"))
    if math.isfinite(number) or "INF" in lexical:
        limit, smallest = (3.4028235e38, 1.4e-45) if single else (math.inf, 0.0)
        mantissa = lexical.lower().split("e")[0].strip("+-").replace(".", "").strip("0")
        if math.isfinite(number) and abs(number) > limit:
            return None
        if mantissa and (number == 0 or abs(number) < smallest):
            return None  # underflow: a non-zero lexical form the type cannot hold
        if number == 0:  # OWL 2: -0 and +0 are distinct values (XML Schema calls them equal)
            return (space, ("zero", math.copysign(1.0, number)))
        return (space, number)
    return None


def _is_uri(text: str) -> bool:
    if not _URI.fullmatch(text):
        return False
    scheme_less = not re.match(r"[A-Za-z][A-Za-z0-9+.-]*:", text)
    return not (scheme_less and ":" in text.split("/")[0])


def _instant(lexical: str) -> object:
    """A dateTime's value: equal for equal instants (``12:30:15`` and ``12:30:15.00``)."""
    text = lexical.replace("Z", "+00:00")
    try:
        moment = datetime.fromisoformat(text)
    except ValueError:
        return lexical  # years outside 1..9999: compared by lexical form
    return (moment.tzinfo is None, moment)


def is_valid(term: str) -> bool:
    """Is the literal's lexical form valid for its datatype? True for datatypes outside the map."""
    _, datatype, _ = _split(term)
    return datatype not in RL_DATATYPES or _value(term) is not None


def value_key(term: str) -> tuple[str, object] | None:
    """A key equal for two literals exactly when they have the same data value (dt-eq, dt-diff);
    None for ill-typed literals and datatypes outside the map."""
    return _value(term)


@lru_cache(maxsize=65_536)
def value_types(term: str) -> frozenset[str]:
    """Every datatype of the map whose value space holds the literal's value (dt-type2)."""
    value = _value(term)
    if value is None:
        return frozenset()
    space, data = value
    _, datatype, language = _split(term)
    found = {rdfs("Literal")}
    if space == "real":
        assert isinstance(data, Fraction)
        found.update(_REALS)
        if data.denominator == 1:
            number = int(data)
            for name, (low, high) in _BOUNDS.items():
                if (low is None or number >= low) and (high is None or number <= high):
                    found.add(name)
    elif space == "string":
        assert isinstance(data, str)
        found.update(_STRINGS)
        for name, pattern in _STRING_SUBTYPES.items():
            if pattern.fullmatch(data):
                found.add(name)
    elif space == "lang":
        found.update((rdf("langString"), rdf("PlainLiteral")))
    elif datatype is not None:
        found.add(datatype)
        if datatype == xsd("dateTimeStamp"):
            found.add(xsd("dateTime"))
        elif datatype == xsd("dateTime") and _LEXICAL[xsd("dateTimeStamp")].fullmatch(
            _split(term)[0]
        ):
            found.add(xsd("dateTimeStamp"))
    del language
    return frozenset(found)


def in_value_space(term: str, datatype: str) -> bool:
    """Does the literal belong to ``datatype`` (a datatype of the map)? dt-not-type's test."""
    return datatype in value_types(term)
