"""A stand-in for ``rospy``, as much of it as armor_py_api uses, that carries ARMOR's two
services over Engram's HTTP API instead of ROS.

A test puts this directory first on ``sys.path`` (and this module in ``sys.modules["rospy"]``)
and sets :data:`base_url` to a running server. :class:`ServiceProxy` then does what rospy's
does for a caller: it builds the service's request from the call's arguments, sends it, and
returns the service's response class, built from the answer. A request goes as the JSON body
of ``POST <base_url>/<service name>``, field for field as the ROS message (Engram's HTTP
mapping of ``armor_msgs``); an answer other than HTTP 200, or no answer, raises
:class:`ServiceException`, as a failed ROS service call does.
"""

import importlib
import logging
from typing import Any

import httpx

__all__ = [
    "ROSException",
    "ServiceException",
    "ServiceProxy",
    "base_url",
    "logerr",
    "loginfo",
    "logwarn",
    "wait_for_service",
]

base_url = ""
"""The Engram server that answers the services (``http://127.0.0.1:<port>``)."""

_http = httpx.Client(timeout=60.0)  # one connection, kept alive, as a ROS persistent proxy

_log = logging.getLogger("rospy")
loginfo = _log.info
logwarn = _log.warning
logerr = _log.error


class ROSException(Exception):
    """rospy's: the service did not become available in time."""


class ServiceException(Exception):
    """rospy's: the service call failed."""


def wait_for_service(service: str, timeout: float | None = None) -> None:
    """Return once the server answers; :class:`ROSException` if it does not within ``timeout``."""
    try:
        _http.get(base_url + "/health", timeout=timeout or 5.0).raise_for_status()
    except httpx.HTTPError as error:
        raise ROSException(f"timeout exceeded while waiting for service {service}") from error


class ServiceProxy:
    """Calls one of ARMOR's services, as ``rospy.ServiceProxy(name, service_class)`` does."""

    def __init__(self, name: str, service_class: Any) -> None:
        self.resolved_name = name
        self.request_class = service_class._request_class
        self.response_class = service_class._response_class

    def __call__(self, *args: Any, **kwds: Any) -> Any:
        return self.call(*args, **kwds)

    def call(self, *args: Any, **kwds: Any) -> Any:
        request = self._request(args, kwds)
        try:
            answer = _http.post(base_url + self.resolved_name, json=_to_json(request))
        except httpx.HTTPError as error:
            raise ServiceException(
                f"service [{self.resolved_name}] unavailable: {error}"
            ) from error
        if answer.status_code != 200:
            raise ServiceException(
                f"service [{self.resolved_name}] responded with an error: {answer.text}"
            )
        return _from_json(self.response_class, answer.json())

    def _request(self, args: tuple[Any, ...], kwds: dict[str, Any]) -> Any:
        # rospy.msg.args_kwds_to_message: a request of the service's type passes as it is;
        # anything else gives the request's fields in order (armor_py_api passes the one field).
        if kwds:
            return self.request_class(**kwds)
        if len(args) == 1 and getattr(args[0], "_md5sum", None) == self.request_class._md5sum:
            return args[0]
        return self.request_class(*args)


def _to_json(message: Any) -> dict[str, Any]:
    return {
        name: _value_to_json(getattr(message, name), kind)
        for name, kind in zip(message.__slots__, message._slot_types, strict=True)
    }


def _value_to_json(value: Any, kind: str) -> Any:
    if "/" not in kind:
        return list(value) if kind.endswith("[]") else value
    if kind.endswith("[]"):
        return [_to_json(item) for item in value]
    return _to_json(value)


def _from_json(message_class: Any, body: dict[str, Any]) -> Any:
    fields = {}
    for name, kind in zip(message_class.__slots__, message_class._slot_types, strict=True):
        if name not in body:
            continue
        value = body[name]
        if "/" in kind:
            nested = _message_class(kind.removesuffix("[]"))
            if kind.endswith("[]"):
                value = [_from_json(nested, item) for item in value]
            else:
                value = _from_json(nested, value)
        fields[name] = value
    return message_class(**fields)


def _message_class(kind: str) -> Any:
    package, name = kind.split("/")
    return getattr(importlib.import_module(package + ".msg"), name)
