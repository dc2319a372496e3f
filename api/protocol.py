"""The ROS messages of ``armor_msgs`` as JSON models, field for field, with the ROS defaults,
and the one primitive type the client sends and the memory stores.

The wire protocol shared by the server and the robot-side client (:mod:`api.client`): this
module needs pydantic and :mod:`kg.primitive` (the standard library only) so that a robot
importing the client loads nothing of the server or the store.

A primitive travels as ARMOR directives (``ADD IND CLASS``, ``ADD DATAPROP IND centreX ...``:
:func:`api.client.primitive_directives`), which the engine parses back into a
:class:`~kg.primitive.Primitive`; the views return it as JSON, validated by pydantic from the
same dataclass.

>>> ArmorDirectiveReq(command="query").command
'query'
>>> ArmorDirectiveRes().model_dump()["sparql_queried_objects"]
[]
"""

from pydantic import BaseModel, ConfigDict, Field

__all__ = [
    "ArmorDirectiveListReq",
    "ArmorDirectiveListRes",
    "ArmorDirectiveReq",
    "ArmorDirectiveRes",
    "ArmorRequest",
    "ArmorResponse",
    "QueryItem",
]


class _Message(BaseModel):
    model_config = ConfigDict(extra="forbid", strict=True, defer_build=True)


class ArmorDirectiveReq(_Message):
    """``armor_msgs/ArmorDirectiveReq``: one directive."""

    client_name: str = ""
    reference_name: str = ""
    command: str = ""
    primary_command_spec: str = ""
    secondary_command_spec: str = ""
    args: list[str] = Field(default_factory=list)


class QueryItem(_Message):
    """``armor_msgs/QueryItem``: one variable binding of a SPARQL solution."""

    key: str = ""
    value: str = ""


class ArmorDirectiveRes(_Message):
    """``armor_msgs/ArmorDirectiveRes``: the answer to one directive."""

    success: bool = False
    timeout: bool = False
    exit_code: int = 0
    error_description: str = ""
    is_consistent: bool = False
    queried_objects: list[str] = Field(default_factory=list)
    sparql_queried_objects: list[QueryItem] = Field(default_factory=list)


class ArmorRequest(_Message):
    """Body of ``POST /armor_interface_srv`` (``ArmorDirective.srv`` request)."""

    armor_request: ArmorDirectiveReq = Field(default_factory=ArmorDirectiveReq)


class ArmorResponse(_Message):
    """Answer of ``POST /armor_interface_srv``."""

    armor_response: ArmorDirectiveRes


class ArmorDirectiveListReq(_Message):
    """Body of ``POST /armor_interface_serialized_srv`` (``ArmorDirectiveList.srv`` request)."""

    armor_requests: list[ArmorDirectiveReq] = Field(default_factory=list)


class ArmorDirectiveListRes(_Message):
    """Answer of ``POST /armor_interface_serialized_srv``."""

    success: bool = False
    is_consistent: bool = False
    armor_responses: list[ArmorDirectiveRes] = Field(default_factory=list)
