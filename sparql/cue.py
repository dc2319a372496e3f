"""The cue queries (``episodes_cue_<kind>_<n>``), built from ``episodes_cue.rq.template``.

``kind`` is ``count``, ``first``, ``last``, ``list`` or ``head<N>``; ``n`` is the number of role
constraints (0 to 3), bound as ``?key1`` … ``?keyn``; ``?activity`` is always bound.

>>> "LIMIT 10" in cue_query("head10", 2) and "?key2" in cue_query("head10", 2)
True
"""

import re
from functools import cache
from importlib.resources import files
from string import Template

__all__ = ["CUE_NAME", "cue_query"]

CUE_NAME = re.compile(r"episodes_cue_(count|first|last|list|head[1-9][0-9]*)_([0-3])")
"""The names of the cue queries."""

_LINK = "?episode prov:qualifiedAssociation|prov:qualifiedUsage"


@cache
def _template() -> Template:
    return Template(files(__package__).joinpath("episodes_cue.rq.template").read_text("utf-8"))


def cue_query(kind: str, constraints: int) -> str:
    """The text of the cue query of ``kind`` with ``constraints`` role constraints."""
    episodes = "DISTINCT ?episode ?begin"
    select = "(COUNT(DISTINCT ?episode) AS ?count)" if kind == "count" else episodes
    begin = "" if kind == "count" else " ; prov:startedAtTime ?begin"
    if constraints == 0 and kind in ("first", "last"):
        select = "?episode ?begin"  # one pointer, one episode
        match = f"  ?episode engram:{kind}OfActivity ?activity{begin} .\n"
    elif constraints == 0:
        match = f"  ?episode engram:activityName ?activity{begin} .\n"
    else:
        match = f"  ?link1 engram:cueKey ?key1 . {_LINK} ?link1 .\n"
        match += "  ?episode engram:activityName ?name . FILTER (?name = ?activity)\n"
        for i in range(2, constraints + 1):
            match += f"  {_LINK} ?link{i} . ?link{i} engram:cueKey ?k{i} .\n"
            match += f"  FILTER (?k{i} = ?key{i})\n"
        if kind != "count":
            match += "  ?episode prov:startedAtTime ?begin .\n"
    order = {
        "count": "",
        "first": "ORDER BY ?begin ?episode\nLIMIT 1",
        "last": "ORDER BY DESC(?begin) DESC(?episode)\nLIMIT 1",
        "list": "ORDER BY ?begin ?episode",
    }.get(kind)
    if order is None:  # headN
        order = f"ORDER BY ?begin ?episode\nLIMIT {int(kind.removeprefix('head'))}"
    if constraints == 0 and kind in ("first", "last"):
        order = ""
    text = _template().substitute(constraints=constraints, select=select, match=match, order=order)
    return text.rstrip() + "\n"
