"""``client.query``: armor_py_api's ``ArmorQueryClient``."""

import re
from typing import TYPE_CHECKING

from api.client._values import Value, parse_value

if TYPE_CHECKING:
    from api.client._client import ArmorClient

__all__ = ["ArmorQueryClient", "strip_uri"]

_FRAGMENT = re.compile(r"#(.+?)>")


def strip_uri(value: str) -> str:
    """armor_py_api's ``_strip_URI``: ``<http://x#E>`` becomes ``E``.

    >>> strip_uri("<http://bnc/exp-rob-lab/2022-23#E>")
    'E'
    """
    found = _FRAGMENT.findall(value)
    return found[0] if found else value


class ArmorQueryClient:
    """Each method sends one query directive and returns its ``queried_objects``."""

    def __init__(self, client: "ArmorClient") -> None:
        self._client = client

    def ind_b2_class(self, class_name: str, with_URI: bool = False) -> list[str]:
        res = self._client.checked("QUERY", "IND", "CLASS", [class_name])
        return (
            list(res.queried_objects) if with_URI else [strip_uri(o) for o in res.queried_objects]
        )

    def dataprop_b2_ind(self, dataprop_name: str, ind_name: str) -> list[str]:
        """The raw strings, ``"3"^^xsd:integer``, as armor_py_api returns them."""
        return list(
            self._client.checked(
                "QUERY", "DATAPROP", "IND", [dataprop_name, ind_name]
            ).queried_objects
        )

    def dataprop_values_b2_ind(self, dataprop_name: str, ind_name: str) -> list[Value]:
        """:meth:`dataprop_b2_ind` as Python values: ``"3"^^xsd:integer`` is ``3``."""
        return [parse_value(v) for v in self.dataprop_b2_ind(dataprop_name, ind_name)]

    def objectprop_b2_ind(
        self, objectprop_name: str, ind_name: str, with_URI: bool = False
    ) -> list[str]:
        res = self._client.checked("QUERY", "OBJECTPROP", "IND", [objectprop_name, ind_name])
        return (
            list(res.queried_objects) if with_URI else [strip_uri(o) for o in res.queried_objects]
        )

    def check_ind_exists(self, ind_name: str) -> bool:
        """True if the individual has a class other than owl:Thing (never raises for "no")."""
        res = self._client.call("QUERY", "IND", "", [ind_name])
        return res.success and len(res.queried_objects) > 0
