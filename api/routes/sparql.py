"""``/sparql``: the SPARQL 1.1 Protocol, queries only.

All three request forms are served: ``GET ?query=``, ``POST`` of a form
(``application/x-www-form-urlencoded``) and ``POST`` of the query itself
(``application/sparql-query``). Updates are refused with 403: the endpoint is read-only.
A body longer than ``sparql_max_query_bytes`` is refused with 413 while it is being read; the
query itself is parsed, checked and run only in the sandbox's worker processes. Without
``default-graph-uri``, the default graph is the live memory, every graph but the trash
(:mod:`kg.datasets`).
"""

from urllib.parse import parse_qs

from fastapi import APIRouter, HTTPException, Request, Response, status
from starlette.concurrency import run_in_threadpool

from api.deps import RunnerDep, SettingsDep, StoreDep
from api.negotiation import NotAcceptable, choose_media_type
from api.openapi_errors import error_responses
from kg.datasets import analyst_default_graphs
from kg.sandbox import QueryForm

router = APIRouter(tags=["sparql"])

_READ_ONLY = "this SPARQL endpoint is read-only: updates are refused"
_FORM_TYPES = ("application/x-www-form-urlencoded",)
_QUERY_TYPES = ("application/sparql-query",)
_UPDATE_TYPES = ("application/sparql-update",)


def _single(values: list[str], name: str) -> str:
    if len(values) != 1:
        raise HTTPException(
            status.HTTP_400_BAD_REQUEST,
            f"{name}: expected exactly one value, got {len(values)}",
        )
    return values[0]


async def _answer(
    request: Request, runner: RunnerDep, store: StoreDep, params: dict[str, list[str]]
) -> Response:
    if "update" in params:
        raise HTTPException(status.HTTP_403_FORBIDDEN, _READ_ONLY)
    text = _single(params.get("query", []), "query")
    named_graphs = params.get("named-graph-uri") or None
    # The live memory by default; the trash by name (kg.datasets).
    default_graphs = params.get("default-graph-uri") or (
        None if named_graphs else analyst_default_graphs(store)
    )
    format_param = next(
        (params[k][0] for k in ("format", "output", "results") if params.get(k)), None
    )
    media_types: dict[QueryForm, str] = {}
    refusals: dict[QueryForm, NotAcceptable] = {}
    for form in QueryForm:
        try:
            media_types[form] = choose_media_type(form, request.headers.get("accept"), format_param)
        except NotAcceptable as error:
            refusals[form] = error
    answer = await run_in_threadpool(
        runner.run,
        text,
        media_types=media_types,
        default_graphs=default_graphs,
        named_graphs=named_graphs,
    )
    if answer.media_type is None:
        raise refusals[answer.form]
    return Response(answer.body, media_type=answer.media_type, headers={"Vary": "Accept"})


async def _limited_body(request: Request, limit: int) -> bytes:
    """The request body, refused with 413 as soon as it is known to pass ``limit`` bytes."""
    too_large = HTTPException(
        status.HTTP_413_CONTENT_TOO_LARGE,
        f"request body: longer than the limit of {limit} bytes (sparql_max_query_bytes)",
    )
    declared = request.headers.get("content-length", "")
    if declared.isdigit() and int(declared) > limit:
        raise too_large
    chunks: list[bytes] = []
    size = 0
    async for chunk in request.stream():
        size += len(chunk)
        if size > limit:
            raise too_large
        chunks.append(chunk)
    return b"".join(chunks)


def _url_params(request: Request) -> dict[str, list[str]]:
    params: dict[str, list[str]] = {}
    for key, value in request.query_params.multi_items():
        params.setdefault(key, []).append(value)
    return params


_QUERY_PARAMETERS = [
    {"name": name, "in": "query", "required": required, "schema": {"type": "string"}}
    for name, required in (
        ("query", False),
        ("default-graph-uri", False),
        ("named-graph-uri", False),
        ("format", False),
    )
]
_POST_BODY = {
    "required": True,
    "content": {
        "application/sparql-query": {"schema": {"type": "string"}},
        "application/x-www-form-urlencoded": {
            "schema": {
                "type": "object",
                "properties": {"query": {"type": "string"}},
                "required": ["query"],
            }
        },
    },
}


@router.get(
    "/sparql",
    summary="SPARQL query by GET",
    responses=error_responses(400, 403, 406, 413, 503),
    openapi_extra={"parameters": _QUERY_PARAMETERS},
)
async def sparql_get(request: Request, runner: RunnerDep, store: StoreDep) -> Response:
    """Answer ``?query=`` with optional ``default-graph-uri`` and ``named-graph-uri``."""
    return await _answer(request, runner, store, _url_params(request))


@router.post(
    "/sparql",
    summary="SPARQL query by POST",
    responses=error_responses(400, 403, 406, 413, 415, 503),
    openapi_extra={"parameters": _QUERY_PARAMETERS, "requestBody": _POST_BODY},
)
async def sparql_post(
    request: Request, runner: RunnerDep, store: StoreDep, settings: SettingsDep
) -> Response:
    """Answer a form-encoded ``query=`` or a body of type ``application/sparql-query``."""
    content_type = request.headers.get("content-type", "").split(";")[0].strip().lower()
    params = _url_params(request)
    body = await _limited_body(request, settings.sparql_max_query_bytes)
    try:
        text = body.decode("utf-8")
    except UnicodeDecodeError as error:
        raise HTTPException(
            status.HTTP_400_BAD_REQUEST, f"request body: not UTF-8 ({error})"
        ) from None
    if content_type in _UPDATE_TYPES:
        raise HTTPException(status.HTTP_403_FORBIDDEN, _READ_ONLY)
    if content_type in _FORM_TYPES:
        for key, values in parse_qs(text, keep_blank_values=True).items():
            params.setdefault(key, []).extend(values)
    elif content_type in _QUERY_TYPES:
        if "query" in params:
            raise HTTPException(
                status.HTTP_400_BAD_REQUEST,
                "query: given both in the URL and as the body; send it once",
            )
        params["query"] = [text]
    else:
        raise HTTPException(
            status.HTTP_415_UNSUPPORTED_MEDIA_TYPE,
            f"Content-Type: got {content_type or 'none'!r}, expected "
            "application/x-www-form-urlencoded or application/sparql-query",
        )
    return await _answer(request, runner, store, params)
