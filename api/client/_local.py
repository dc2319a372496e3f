"""An httpx transport that answers the client's directives in this process, with no server.

``engram perceive --local`` and the demo use it, so they run the very code path a remote client
does (the same requests, models and responses) without HTTP or a second process.
"""

import json

import httpx

from api.armor import ArmorDirectiveListReq, ArmorEngine
from api.armor.models import ArmorRequest

__all__ = ["LocalTransport"]


class LocalTransport(httpx.BaseTransport):
    """Dispatch ``/armor_interface_srv`` and ``/armor_interface_serialized_srv`` to ``engine``.

    Bad bodies answer 422 as the server would; other paths 404.
    """

    def __init__(self, engine: ArmorEngine) -> None:
        self.engine = engine

    def handle_request(self, request: httpx.Request) -> httpx.Response:
        path = request.url.path
        try:
            body = json.loads(request.read() or b"{}")
            if path.endswith("/armor_interface_srv"):
                one = ArmorRequest.model_validate(body).armor_request
                answer = {"armor_response": self.engine.execute(one).model_dump()}
            elif path.endswith("/armor_interface_serialized_srv"):
                many = ArmorDirectiveListReq.model_validate(body).armor_requests
                answer = self.engine.execute_list(many).model_dump()
            else:
                return httpx.Response(404, json={"detail": f"no local route for {path}"})
        except ValueError as error:  # bad JSON or a body that does not validate
            return httpx.Response(422, json={"detail": str(error)})
        return httpx.Response(200, json=answer)
