"""``ArmorClient``: armor_py_api's client, over HTTP instead of ROS."""

from dataclasses import dataclass, field
from types import TracebackType
from typing import TYPE_CHECKING, Any

import httpx

from api.client._manipulation import ArmorManipulationClient
from api.client._memory import ArmorMemoryClient
from api.client._query import ArmorQueryClient
from api.client._utils import ArmorUtilsClient
from api.client._values import parse_value
from api.client.exceptions import ArmorServiceCallError, directive_error

if TYPE_CHECKING:
    from api.protocol import ArmorDirectiveListRes, ArmorDirectiveRes

__all__ = ["Answer", "ArmorClient"]

_TIMEOUT_MESSAGE = "Cannot reach ARMOR client: Timeout Expired. Check if ARMOR is running."


def _named(value: Any) -> Any:
    """``value`` with every IRI in it (at any depth) as its name."""
    if isinstance(value, str) and value.startswith(("http://", "https://")) and " " not in value:
        return parse_value(f"<{value}>")
    if isinstance(value, list):
        return [_named(v) for v in value]
    if isinstance(value, dict):
        return {k: _named(v) for k, v in value.items()}
    return value


@dataclass(frozen=True)
class Answer:
    """The memory's answer to a question in words (``POST /ask``): ``words`` to say, whether
    the question was ``understood``, its structured ``answer`` with names and numbers as values,
    and ``suggestions`` of questions it understands when it was not."""

    question: str
    understood: bool
    words: str
    answer: dict[str, Any] = field(default_factory=dict)
    suggestions: tuple[str, ...] = ()
    body: dict[str, Any] = field(default_factory=dict)
    """The whole JSON answer (explanations, the SPARQL it ran)."""

    @classmethod
    def of(cls, body: dict[str, Any]) -> "Answer":
        answer = {key: _named(value) for key, value in (body.get("answer") or {}).items()}
        return cls(
            question=str(body.get("question", "")),
            understood=bool(body.get("understood")),
            words=str(body.get("words", "")),
            answer=answer,
            suggestions=tuple(body.get("suggestions") or ()),
            body=body,
        )


class ArmorClient:
    """A client of one reference, with armor_py_api's ``.manipulation``, ``.query``, ``.utils``
    (and Engram's ``.memory``).

    ``timeout`` is in seconds, as armor_py_api's. Existing code ports by changing the import and
    passing ``base_url`` (and ``token`` when the server has ``ENGRAM_TOKEN`` set).
    """

    def __init__(
        self,
        client_id: str,
        reference_name: str,
        service_name: str = "/armor_interface_srv",
        serial_service_name: str = "/armor_interface_serialized_srv",
        timeout: float = 5,
        *,
        base_url: str = "http://127.0.0.1:8000",
        token: str | None = None,
        http: httpx.Client | None = None,
    ) -> None:
        self.client_id = client_id
        self.reference_name = reference_name
        self.service_name = service_name
        self.serial_service_name = serial_service_name
        self.timeout = timeout
        headers = {"Authorization": f"Bearer {token}"} if token else {}
        self._owns_http = http is None
        self._http = http or httpx.Client(base_url=base_url, timeout=timeout, headers=headers)
        self.manipulation = ArmorManipulationClient(self)
        self.query = ArmorQueryClient(self)
        self.utils = ArmorUtilsClient(self)
        self.memory = ArmorMemoryClient(self)

    def close(self) -> None:
        """Close the HTTP connections (only if the client opened them)."""
        if self._owns_http:
            self._http.close()

    def __enter__(self) -> "ArmorClient":
        return self

    def __exit__(
        self,
        kind: type[BaseException] | None,
        error: BaseException | None,
        trace: TracebackType | None,
    ) -> None:
        self.close()

    def _request(self, command: str, first: str, second: str, args: list[str]) -> dict[str, Any]:
        from api.protocol import ArmorDirectiveReq  # pydantic: loaded on the first directive

        return ArmorDirectiveReq(
            client_name=self.client_id,
            reference_name=self.reference_name,
            command=command,
            primary_command_spec=first,
            secondary_command_spec=second,
            args=[str(arg) for arg in args],
        ).model_dump()

    def _post(self, path: str, body: dict[str, Any]) -> dict[str, Any]:
        try:
            response = self._http.post(path, json=body)
        except httpx.TimeoutException:
            raise ArmorServiceCallError(_TIMEOUT_MESSAGE) from None
        except httpx.HTTPError as error:
            raise ArmorServiceCallError(
                f"Cannot reach ARMOR at {self._http.base_url}: {error}"
            ) from None
        if response.status_code != 200:
            try:
                detail = response.json().get("detail", response.text)
            except ValueError:
                detail = response.text
            raise ArmorServiceCallError(f"Service call failed ({response.status_code}): {detail}")
        data: dict[str, Any] = response.json()
        return data

    def call(
        self, command: str, first_spec: str, second_spec: str, args_list: list[str]
    ) -> "ArmorDirectiveRes":
        """Send one directive and return the raw ``armor_response`` (no exception on failure)."""
        from api.protocol import ArmorDirectiveRes

        body = {"armor_request": self._request(command, first_spec, second_spec, args_list)}
        data = self._post(self.service_name, body)
        return ArmorDirectiveRes.model_validate(data["armor_response"])

    def call_list(
        self, directives: list[tuple[str, str, str, list[str]]]
    ) -> "ArmorDirectiveListRes":
        """Send directives to the list service: in order, one transaction, one response each."""
        from api.protocol import ArmorDirectiveListRes

        body = {"armor_requests": [self._request(*directive) for directive in directives]}
        return ArmorDirectiveListRes.model_validate(self._post(self.serial_service_name, body))

    def raise_first_failure(self, result: "ArmorDirectiveListRes") -> "list[ArmorDirectiveRes]":
        """The list's responses; raises for the first failed one (the list changed nothing)."""
        for response in result.armor_responses:
            if not response.success and response.exit_code != 0:
                raise directive_error(response.error_description, response.exit_code)
        return list(result.armor_responses)

    def checked(
        self, command: str, first_spec: str, second_spec: str, args_list: list[str]
    ) -> "ArmorDirectiveRes":
        """:meth:`call`, raising :class:`ArmorServiceInternalError` when ``success`` is false
        (:class:`ArmorInputError` when the input was wrong)."""
        response = self.call(command, first_spec, second_spec, args_list)
        if not response.success:
            raise directive_error(response.error_description, response.exit_code)
        return response

    def ask(self, question: str) -> "Answer":
        """Ask the memory a question in words (``POST /ask``); raises :class:`ValueError` for
        an empty or overlong question and :class:`ArmorServiceCallError` if the server cannot
        be reached or refuses it."""
        if not isinstance(question, str) or not question.strip():
            raise ValueError(f"question: got {question!r}, expected a question in words")
        return Answer.of(self._post("/ask", {"text": question}))
