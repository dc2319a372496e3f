"""``client.manipulation``: armor_py_api's ``ArmorManipulationClient``."""

import re
from typing import TYPE_CHECKING

from api.client.exceptions import ArmorServiceInternalError

if TYPE_CHECKING:
    from api.client._client import ArmorClient

__all__ = ["ArmorManipulationClient", "literal_value"]

_TYPED = re.compile(r'^"((?:[^"\\]|\\.)*)"(?:\^\^.+|@[\w-]+)?$')


def literal_value(raw: str) -> str:
    """The lexical value of ARMOR's ``"3"^^xsd:integer`` (or a bare value, unchanged).

    >>> literal_value('"3"^^xsd:integer')
    '3'
    >>> literal_value("3")
    '3'
    """
    match = _TYPED.match(raw)
    if match is None:
        return raw
    return match.group(1).replace('\\"', '"').replace("\\\\", "\\")


class ArmorManipulationClient:
    """Each method sends one directive and returns ``is_consistent``.

    Raises :class:`ArmorServiceInternalError` when ARMOR answers ``success=false`` and
    :class:`ArmorServiceCallError` when the call fails.
    """

    def __init__(self, client: "ArmorClient") -> None:
        self._client = client

    def _do(self, command: str, first: str, second: str, args: list[str]) -> bool:
        return self._client.checked(command, first, second, args).is_consistent

    def add_ind_to_class(self, ind_name: str, class_name: str) -> bool:
        return self._do("ADD", "IND", "CLASS", [ind_name, class_name])

    def disj_inds_of_class(self, class_name: str) -> bool:
        return self._do("DISJOINT", "IND", "CLASS", [class_name])

    def disj_inds(self, inds: list[str]) -> bool:
        """``DISJOINT IND`` over a list (the wrapper armor_py_api users asked for)."""
        return self._do("DISJOINT", "IND", "", list(inds))

    def add_objectprop_to_ind(
        self, objectprop_name: str, ind_name: str, value_obj_name: str
    ) -> bool:
        return self._do("ADD", "OBJECTPROP", "IND", [objectprop_name, ind_name, value_obj_name])

    def add_dataprop_to_ind(
        self, dataprop_name: str, ind_name: str, value_type: str, value: str
    ) -> bool:
        return self._do("ADD", "DATAPROP", "IND", [dataprop_name, ind_name, value_type, str(value)])

    def add_batch_dataprop_to_ind(self, ind_name: str, dataprops: list[list[str]]) -> bool:
        """``[[prop, type, value], ...]``; False at the first inconsistent result."""
        for prop, value_type, value in dataprops:
            if not self.add_dataprop_to_ind(prop, ind_name, value_type, value):
                return False
        return True

    def replace_objectprop_b2_ind(
        self, objectprop_name: str, ind_name: str, new_value: str, old_value: str
    ) -> bool:
        return self._do(
            "REPLACE", "OBJECTPROP", "IND", [objectprop_name, ind_name, new_value, old_value]
        )

    def replace_dataprop_b2_ind(
        self, dataprop_name: str, ind_name: str, value_type: str, new_value: str, old_value: str
    ) -> bool:
        return self._do(
            "REPLACE",
            "DATAPROP",
            "IND",
            [dataprop_name, ind_name, value_type, str(new_value), literal_value(str(old_value))],
        )

    def replace_one_dataprop_b2_ind(
        self, dataprop_name: str, ind_name: str, value_type: str, new_value: str
    ) -> bool:
        """Set the only value: ADD if there is none, REPLACE if one, error 206 if several.

        Fixed: armor_py_api passed the raw ``"3"^^xsd:integer`` as the old value, which ARMOR
        cannot cast; the lexical value is passed here.
        """
        values = self._client.query.dataprop_b2_ind(dataprop_name, ind_name)
        if not values:
            return self.add_dataprop_to_ind(dataprop_name, ind_name, value_type, new_value)
        if len(values) == 1:
            return self.replace_dataprop_b2_ind(
                dataprop_name, ind_name, value_type, new_value, literal_value(values[0])
            )
        raise ArmorServiceInternalError(
            f"You are trying to replace a single value of {dataprop_name} belonging to "
            f"{ind_name} but it has multiple values.",
            "206",
        )

    def replace_one_objectprop_b2_ind(
        self, objectprop_name: str, ind_name: str, new_value: str
    ) -> bool:
        values = self._client.query.objectprop_b2_ind(objectprop_name, ind_name)
        if not values:
            return self.add_objectprop_to_ind(objectprop_name, ind_name, new_value)
        if len(values) == 1:
            return self.replace_objectprop_b2_ind(objectprop_name, ind_name, new_value, values[0])
        raise ArmorServiceInternalError(
            f"You are trying to replace a single value of {objectprop_name} belonging to "
            f"{ind_name} but it has multiple values.",
            "206",
        )

    def remove_dataprop_from_ind(
        self, dataprop_name: str, ind_name: str, value_type: str, value: str
    ) -> bool:
        return self._do(
            "REMOVE",
            "DATAPROP",
            "IND",
            [dataprop_name, ind_name, value_type, literal_value(str(value))],
        )

    def remove_batch_dataprop_to_ind(self, ind_name: str, dataprops: list[list[str]]) -> bool:
        """``[[prop, type, value], ...]``; False at the first inconsistent result.

        Fixed: armor_py_api swapped the individual and the property.
        """
        for prop, value_type, value in dataprops:
            if not self.remove_dataprop_from_ind(prop, ind_name, value_type, value):
                return False
        return True

    def remove_objectprop_from_ind(
        self, objectprop_name: str, ind_name: str, value_obj_name: str
    ) -> bool:
        return self._do("REMOVE", "OBJECTPROP", "IND", [objectprop_name, ind_name, value_obj_name])

    def remove_ind_from_class(self, ind_name: str, class_name: str) -> bool:
        return self._do("REMOVE", "IND", "CLASS", [ind_name, class_name])
