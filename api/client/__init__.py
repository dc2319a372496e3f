"""A Python client of Engram's ARMOR directive API, with armor_py_api's names.

Existing armor_py_api code ports by changing the import::

    from api.client import ArmorClient   # was: from armor_api.armor_client import ArmorClient

    client = ArmorClient("client", "reference", base_url="http://127.0.0.1:8000")
    client.utils.load_ref_from_file("test.owl", "http://ex.org/test", True, "PELLET", True)
    client.manipulation.add_ind_to_class("ind_1", "Class_1")

Beside armor_py_api's strings, answers come as Python values (``MemoryAnswer.typed_values``,
``typed_details``, ``query.dataprop_values_b2_ind``: IRIs as names, numbers as numbers),
``client.ask("...")`` asks in words, and a directive refused for its input raises
:class:`ArmorInputError` (a ``ValueError``) saying what was wrong.

Fixed armor_py_api bugs: ``utils.set_log_to_file(False)`` works,
``manipulation.remove_batch_dataprop_to_ind`` passes its arguments in the right order, and
``manipulation.replace_one_dataprop_b2_ind`` sends the old value's lexical form.
"""

from typing import TYPE_CHECKING, Any

from api.client._client import Answer, ArmorClient
from api.client._manipulation import ArmorManipulationClient, literal_value
from api.client._memory import (
    ArmorMemoryClient,
    MemoryAnswer,
    Primitive,
    primitive_directives,
    scene_directives,
)
from api.client._query import ArmorQueryClient, strip_uri
from api.client._utils import ArmorUtilsClient
from api.client._values import Value, parse_value
from api.client.exceptions import (
    ArmorInputError,
    ArmorPyException,
    ArmorServiceCallError,
    ArmorServiceInternalError,
)

if TYPE_CHECKING:
    from api.client._local import LocalTransport

__all__ = [
    "Answer",
    "ArmorClient",
    "ArmorInputError",
    "ArmorManipulationClient",
    "ArmorMemoryClient",
    "ArmorPyException",
    "ArmorQueryClient",
    "ArmorServiceCallError",
    "ArmorServiceInternalError",
    "ArmorUtilsClient",
    "LocalTransport",
    "MemoryAnswer",
    "Primitive",
    "Value",
    "literal_value",
    "parse_value",
    "primitive_directives",
    "scene_directives",
    "strip_uri",
]


def __getattr__(name: str) -> Any:
    """``LocalTransport`` runs the engine in this process: it is imported only when asked for,
    so that ``import api.client`` on a robot loads nothing of the server."""
    if name == "LocalTransport":
        from api.client._local import LocalTransport

        return LocalTransport
    raise AttributeError(f"module 'api.client' has no attribute {name!r}")
