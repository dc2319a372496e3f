"""Choosing the media type of a SPARQL answer from the Accept header or a ``format`` parameter.

>>> from kg.sandbox import QueryForm
>>> choose_media_type(QueryForm.SOLUTIONS, "text/csv;q=0.5, application/sparql-results+xml")
'application/sparql-results+xml'
>>> choose_media_type(QueryForm.GRAPH, "*/*")
'text/turtle'
"""

from kg.sandbox import RESULT_FORMATS, QueryForm

__all__ = ["NotAcceptable", "choose_media_type"]

# Common aliases clients send, and the short names of the `format` parameter that SPARQLWrapper,
# Virtuoso and others use.
_ALIASES: dict[QueryForm | None, dict[str, str]] = {
    None: {
        "application/json": "application/sparql-results+json",
        "json": "application/sparql-results+json",
        "application/xml": "application/sparql-results+xml",
        "text/xml": "application/sparql-results+xml",
        "xml": "application/sparql-results+xml",
        "csv": "text/csv",
        "tsv": "text/tab-separated-values",
    },
    QueryForm.GRAPH: {
        "application/xml": "application/rdf+xml",
        "text/xml": "application/rdf+xml",
        "xml": "application/rdf+xml",
        "rdf": "application/rdf+xml",
        "rdf+xml": "application/rdf+xml",
        "turtle": "text/turtle",
        "ttl": "text/turtle",
        "n3": "text/turtle",
        "text/n3": "text/turtle",
        "application/x-turtle": "text/turtle",
        "nt": "application/n-triples",
        "ntriples": "application/n-triples",
        "n-triples": "application/n-triples",
        "text/plain": "application/n-triples",
        "json-ld": "application/ld+json",
        "jsonld": "application/ld+json",
        "application/json": "application/ld+json",
        "json": "application/ld+json",
    },
}


class NotAcceptable(ValueError):
    """No media type the client accepts can carry this kind of answer."""


def _canonical(form: QueryForm, name: str) -> str | None:
    name = name.strip().lower()
    offered = RESULT_FORMATS[form]
    if name in offered:
        return name
    aliases = _ALIASES[QueryForm.GRAPH] if form is QueryForm.GRAPH else _ALIASES[None]
    return aliases.get(name)


def choose_media_type(form: QueryForm, accept: str | None, format_param: str | None = None) -> str:
    """The media type to answer a query of ``form`` in.

    A recognised ``format`` parameter wins over the Accept header; otherwise the acceptable type
    with the highest quality is chosen, ties going to the order of the header. Raises
    :class:`NotAcceptable` when the client accepts nothing this form can be written in.
    """
    offered = list(RESULT_FORMATS[form])
    if format_param:
        chosen = _canonical(form, format_param)
        if chosen is not None:
            return chosen
    if not accept or not accept.strip():
        return offered[0]
    ranked: list[tuple[float, int, str]] = []
    for position, item in enumerate(accept.split(",")):
        media, *params = (part.strip() for part in item.split(";"))
        quality = 1.0
        for param in params:
            key, _, value = param.partition("=")
            if key.strip().lower() == "q":
                try:
                    quality = float(value)
                except ValueError:
                    quality = 0.0
        if quality <= 0 or not media:
            continue
        media = media.lower()
        if media == "*/*":
            candidate: str | None = offered[0]
        elif media.endswith("/*"):
            prefix = media[:-1]
            candidate = next((o for o in offered if o.startswith(prefix)), None)
        else:
            candidate = _canonical(form, media)
        if candidate is not None:
            ranked.append((-quality, position, candidate))
    if not ranked:
        raise NotAcceptable(
            f"Accept: got {accept!r}; a {form.value} result can be sent as {', '.join(offered)}"
        )
    return min(ranked)[2]
