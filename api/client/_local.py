"""An httpx transport that answers the client's directives in this process, with no server.

``engram perceive --local`` and the demo use it, so they run the very code path a remote client
does (the same requests, models and responses: :mod:`api.directives`) without HTTP or a second
process.
"""

import httpx
from fastapi import HTTPException
from fastapi.encoders import jsonable_encoder
from fastapi.exceptions import RequestValidationError

from api.armor import ArmorEngine
from api.directives import SERVICES, answer_blocking

__all__ = ["LocalTransport"]


class LocalTransport(httpx.BaseTransport):
    """Answer ``POST /armor_interface_srv`` and ``/armor_interface_serialized_srv`` with
    ``engine``, as the server would: bad requests answer 400 or 422 in FastAPI's shapes, other
    methods 405, other paths 404. Errors of the engine are raised to the caller."""

    def __init__(self, engine: ArmorEngine) -> None:
        self.engine = engine

    def handle_request(self, request: httpx.Request) -> httpx.Response:
        path = request.url.path  # under the base URL's path, if it has one
        service = next((s for s in SERVICES.values() if path.endswith(s.path)), None)
        if service is None:
            return httpx.Response(404, json={"detail": "Not Found"})
        if request.method != "POST":
            return httpx.Response(405, json={"detail": "Method Not Allowed"})
        try:
            content = answer_blocking(
                self.engine,
                service,
                request.read(),
                query=request.url.query,
                content_type=request.headers.get("content-type"),
            )
        except RequestValidationError as error:
            return httpx.Response(422, json={"detail": jsonable_encoder(error.errors())})
        except HTTPException as error:
            return httpx.Response(error.status_code, json={"detail": error.detail})
        return httpx.Response(200, content=content, headers={"content-type": "application/json"})
