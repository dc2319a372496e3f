"""Names in ``args`` to IRIs, typed values to literals, and terms back to ARMOR's strings.

ARMOR resolves every name against the IRI given at LOAD: ``<iri>#<name>``. Engram also accepts a
full IRI, written ``<http://…>`` or starting with ``http://``, ``https://`` or ``urn:``.

>>> resolve("ind_1", "http://ex.org/onto").value
'http://ex.org/onto#ind_1'
>>> to_literal("INTEGER", "3", field="args[3]")
<Literal value=3 datatype=<NamedNode value=http://www.w3.org/2001/XMLSchema#integer>>
>>> armor_string(to_literal("FLOAT", "0.5", field="args[3]"))
'"0.5"^^xsd:float'
>>> armor_string(NamedNode("http://ex.org/onto#ind_1"))
'<http://ex.org/onto#ind_1>'
>>> jena_string(to_literal("INT", "3", field="args[3]"))
'3^^http://www.w3.org/2001/XMLSchema#integer'
"""

import decimal
import math
import re
import struct
from typing import Literal as Lit

from pyoxigraph import BlankNode, Literal, NamedNode, Triple

from api.armor.errors import InvalidArgumentsError
from ontologies.vocab import OWL_NS, RDF_NS, RDFS_NS, SKOLEM_PREFIX, XSD_NS

__all__ = [
    "ValueStyle",
    "armor_string",
    "is_true",
    "is_value_type",
    "java_number",
    "jena_string",
    "local_name",
    "plain_string",
    "resolve",
    "styled",
    "to_literal",
]

ValueStyle = Lit["armor", "plain", "short"]
"""How query results are written: ARMOR's strings (``<iri>``, ``"3"^^xsd:integer``), plain values
(``iri``, ``3``), or short names (``ind_1``, ``3``)."""

_FULL_IRI = re.compile(r"^(?:https?://|urn:|file:)\S+$")
_XSD = {
    name: NamedNode(XSD_NS + name) for name in ("string", "integer", "float", "long", "boolean")
}
_TYPES = {
    "STRING": "string",
    "INT": "integer",
    "INTEGER": "integer",
    "FLOAT": "float",
    "DOUBLE": "float",  # ARMOR converts DOUBLE to a Java Float: xsd:float
    "LONG": "long",
    "BOOLEAN": "boolean",
    "BOOL": "boolean",
}
_PREFIXES = (("xsd", XSD_NS), ("rdf", RDF_NS), ("rdfs", RDFS_NS), ("owl", OWL_NS))
_XSD_FLOAT, _XSD_DOUBLE = XSD_NS + "float", XSD_NS + "double"


def resolve(name: str, prefix: str, *, field: str = "args") -> NamedNode:
    """The IRI of a name given in ``args``.

    Raises :class:`InvalidArgumentsError` for an empty name or one that cannot be in an IRI.
    """
    if name.startswith("<") and name.endswith(">"):
        iri = name[1:-1]
    elif _FULL_IRI.match(name):
        iri = name
    else:
        if not name:
            raise InvalidArgumentsError(f"{field}: got an empty name, expected an entity name")
        # The OWL API takes any text after the '#' ("living room"); an RDF IRI cannot hold
        # these characters, so they are stored percent-encoded and printed back as given.
        iri = f"{prefix}#{_UNSAFE.sub(lambda m: _ENCODED[m.group()], name)}"
    try:
        return NamedNode(iri)
    except ValueError:
        raise InvalidArgumentsError(
            f"{field}: got {name!r}, which cannot be part of an IRI (a control character?)"
        ) from None


def is_true(flag: str) -> bool:
    """Java's ``Boolean.valueOf``: ``"true"`` in any case is true, anything else false."""
    return flag.lower() == "true"


def is_value_type(type_name: str) -> bool:
    """True for the type names ARMOR accepts (case-insensitive)."""
    return type_name.upper() in _TYPES


def to_literal(type_name: str, value: str, *, field: str) -> Literal:
    """The literal ARMOR makes of ``value`` with ``type_name`` (STRING, INTEGER, DOUBLE, …).

    The caller checks :func:`is_value_type` first (ARMOR answers 101 for an unknown type). Raises
    :class:`InvalidArgumentsError` naming ``field`` for a value that is not of the type.
    """
    local = _TYPES[type_name.upper()]
    if local == "integer" or local == "long":
        if not _JAVA_INTEGER.fullmatch(value):
            raise InvalidArgumentsError(
                f"{field}: got {value!r}, expected an integer for type {type_name} "
                "(an optional sign and ASCII digits, as Java's parseInt reads them)"
            )
        number = int(value)
        bits = 32 if local == "integer" else 64
        if not -(2 ** (bits - 1)) <= number < 2 ** (bits - 1):
            raise InvalidArgumentsError(
                f"{field}: got {value!r}, out of range for type {type_name} ({bits}-bit)"
            )
        return Literal(str(number), datatype=_XSD[local])
    if local == "float":
        return Literal(_java_float(value, field=field, type_name=type_name), datatype=_XSD[local])
    if local == "boolean":
        return Literal("true" if is_true(value) else "false", datatype=_XSD[local])
    return Literal(value, datatype=_XSD["string"])


_JAVA_INTEGER = re.compile(r"[+-]?[0-9]+")
"""``Integer.parseInt`` / ``Long.parseLong`` with ASCII digits: no spaces, underscores or
other scripts' digits (Python's ``int`` takes all three)."""
_JAVA_DECIMAL = re.compile(r"[+-]?(?:[0-9]+\.?[0-9]*|\.[0-9]+)(?:[eE][+-]?[0-9]+)?[fFdD]?")
_JAVA_HEX = re.compile(
    r"([+-]?)0[xX]((?:[0-9a-fA-F]+\.?[0-9a-fA-F]*|\.[0-9a-fA-F]+)[pP][+-]?[0-9]+)[fFdD]?"
)


def java_number(value: str, *, field: str, type_name: str = "DOUBLE") -> float:
    """``value`` read as Java's ``Double.parseDouble`` reads a finite numeral.

    Leading and trailing control characters and spaces are ignored, as Java trims them; a
    type suffix (``f``, ``d``) and hexadecimal numerals (``0x1.8p1``) are accepted. Python's
    extras (``nan``, ``inf``, ``1_000``, other scripts' digits) are not, and neither are Java's
    ``NaN`` and ``Infinity`` nor a numeral too large for a double: a measurement must be finite.
    Raises :class:`InvalidArgumentsError` (208) naming ``field``.

    >>> java_number(" 1.5e3d", field="args[3]")
    1500.0
    >>> java_number("1_000", field="args[3]")  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    api.armor.errors.InvalidArgumentsError: args[3]: got '1_000', expected a finite decimal...
    """
    text = value.strip("".join(chr(c) for c in range(33)))
    number: float | None = None
    if _JAVA_DECIMAL.fullmatch(text):
        number = float(text.rstrip("fFdD"))
    elif hexadecimal := _JAVA_HEX.fullmatch(text):
        try:
            number = float.fromhex(hexadecimal.group(1) + "0x" + hexadecimal.group(2))
        except OverflowError:
            number = math.inf
    if number is None or not math.isfinite(number):
        raise InvalidArgumentsError(
            f"{field}: got {value!r}, expected a finite decimal number for type {type_name} "
            "(Java's syntax: digits, '.', an exponent; no NaN, Infinity, underscores or "
            "non-ASCII digits)"
        )
    return number


def _java_float(value: str, *, field: str, type_name: str) -> str:
    """The shortest decimal that reads back as the same 32-bit float, as Java prints it."""
    number = java_number(value, field=field, type_name=type_name)
    try:
        single = struct.unpack("f", struct.pack("f", number))[0]
    except OverflowError:
        raise InvalidArgumentsError(
            f"{field}: got {value!r}, out of range for a 32-bit float ({type_name})"
        ) from None
    text = repr(single)
    for digits in range(1, 10):
        text = f"{single:.{digits}g}"
        if struct.unpack("f", struct.pack("f", float(text)))[0] == single:
            break
    # Positional notation, as the store writes a canonical xsd:float ("1e10" is "10000000000").
    positional = format(decimal.Decimal(text), "f")
    if "." in positional:
        positional = positional.rstrip("0").rstrip(".")
    return positional or "0"


_ENCODED = {c: f"%{ord(c):02X}" for c in ' <>"{}|\\^`'}
_DECODED = {code: c for c, code in _ENCODED.items()}
_UNSAFE = re.compile("[" + re.escape("".join(_ENCODED)) + "]")
_ESCAPED = re.compile("|".join(_DECODED))


def _as_given(iri: str) -> str:
    """The IRI with the characters :func:`resolve` percent-encoded written as given again."""
    return _ESCAPED.sub(lambda m: _DECODED[m.group()], iri) if "%" in iri else iri


def local_name(iri: str) -> str:
    """The part after ``#`` (or the last ``/``): ARMOR's short name."""
    iri = _as_given(iri)
    for separator in ("#", "/"):
        if separator in iri:
            return iri.rsplit(separator, 1)[1]
    return iri


def java_decimal(lexical: str, *, single: bool) -> str:
    """Java's ``Float.toString`` (``single``) or ``Double.toString`` of a stored value: ``2.0``
    for 2, ``1.0E10`` for 10000000000, ``1.0E-4`` for 0.0001; the lexical form if it is not a
    number.

    >>> java_decimal("10000000000", single=True), java_decimal("0.5", single=False)
    ('1.0E10', '0.5')
    """
    try:
        number = float(lexical.replace("INF", "inf"))
    except ValueError:
        return lexical
    if math.isnan(number):
        return "NaN"
    if math.isinf(number):
        return "Infinity" if number > 0 else "-Infinity"
    if number == 0:
        return "-0.0" if math.copysign(1, number) < 0 else "0.0"
    text = repr(number)
    if single:
        single_value = struct.unpack("f", struct.pack("f", number))[0]
        for precision in range(1, 10):
            text = f"{single_value:.{precision}g}"
            if struct.unpack("f", struct.pack("f", float(text)))[0] == single_value:
                break
    sign, digits, exponent = decimal.Decimal(text).normalize().as_tuple()
    assert isinstance(exponent, int)
    mantissa = "".join(str(digit) for digit in digits)
    point = len(mantissa) + exponent  # the decimal point sits after this many digits
    if 1e-3 <= abs(number) < 1e7:
        if point <= 0:
            body = "0." + "0" * -point + mantissa
        elif point >= len(mantissa):
            body = mantissa + "0" * (point - len(mantissa)) + ".0"
        else:
            body = mantissa[:point] + "." + mantissa[point:]
    else:
        body = f"{mantissa[0]}.{mantissa[1:] or '0'}E{point - 1}"
    return ("-" if sign else "") + body


def _escape(text: str) -> str:
    return text.replace("\\", "\\\\").replace('"', '\\"')


def _prefixed(iri: str) -> str:
    """The OWL API's rendering of an IRI: ``owl:Nothing`` in the built-in namespaces, else
    ``<iri>``."""
    for prefix, namespace in _PREFIXES:
        if iri.startswith(namespace):
            return f"{prefix}:{iri[len(namespace) :]}"
    return f"<{_as_given(iri)}>"


def _lexical(term: Literal) -> str:
    """The lexical form the OWL API holds: Java's text for floats and doubles (the store keeps
    them positional, ``2`` for ``2.0``)."""
    datatype = term.datatype.value
    if datatype in (_XSD_FLOAT, _XSD_DOUBLE):
        return java_decimal(term.value, single=datatype == _XSD_FLOAT)
    return term.value


def armor_string(term: NamedNode | BlankNode | Literal | Triple) -> str:
    """ARMOR's (the OWL API's ``toString``) string for a term: ``<iri>``, ``owl:Nothing``,
    ``"lex"^^xsd:type``."""
    if isinstance(term, Literal):
        if term.language:
            return f'"{_escape(term.value)}"@{term.language}'
        return f'"{_escape(_lexical(term))}"^^{_prefixed(term.datatype.value)}'
    if isinstance(term, NamedNode):
        return _prefixed(term.value)
    return str(term)


def plain_string(term: NamedNode | BlankNode | Literal | Triple) -> str:
    """The IRI without brackets, or the literal's lexical value."""
    if isinstance(term, Literal):
        return _lexical(term)
    if isinstance(term, NamedNode):
        return _as_given(term.value)
    return str(term)


def styled(term: NamedNode | BlankNode | Literal | Triple, style: ValueStyle) -> str:
    """A query result in the chosen :data:`ValueStyle`."""
    if style == "armor":
        return armor_string(term)
    if style == "short" and isinstance(term, NamedNode):
        return local_name(term.value)
    return plain_string(term)


def jena_string(term: NamedNode | BlankNode | Literal | Triple) -> str:
    """Jena's ``RDFNode.toString()``: ``iri``, ``lex^^datatype-iri``, ``lex@lang`` or ``lex``."""
    if isinstance(term, Literal):
        if term.language:
            return f"{term.value}@{term.language}"
        if term.datatype.value == XSD_NS + "string":
            return term.value
        return f"{_lexical(term)}^^{term.datatype.value}"
    if isinstance(term, NamedNode):
        if term.value.startswith(SKOLEM_PREFIX):
            return term.value[len(SKOLEM_PREFIX) :]  # Jena prints a blank node as its label
        return _as_given(term.value)
    return str(term)
