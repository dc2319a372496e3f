"""``/ask``, ``/ask/audio`` and ``/explain``: the memory asked in words, in speech, and why.

Asking recalls from the scene memory, which strengthens what is recalled, so both ``/ask``
routes are writes (they need the token when one is set); ``/explain`` only reads.
"""

import base64
import threading
from typing import Annotated, Any, Literal

from fastapi import APIRouter, Depends, Query, Request, Response
from pydantic import BaseModel, Field
from starlette.concurrency import run_in_threadpool

from api.ask import Asker
from api.ask.asker import MAX_QUESTION
from api.ask.speech import MAX_AUDIO_S, Recogniser, synthesise
from api.deps import require_token
from api.openapi_errors import error_responses
from api.routes.names import memory_iri
from kg.errors import InvalidValueError
from reasoners.explain import explain, to_jsonable

router = APIRouter(tags=["ask"])

_LOCK = threading.Lock()
MAX_AUDIO_BYTES = int(MAX_AUDIO_S * 48_000 * 2 * 2) + 1024
"""30 s of 48 kHz 16-bit stereo, and a header."""


class AskRequest(BaseModel):
    """A question in words."""

    text: str = Field(min_length=1, max_length=MAX_QUESTION, examples=["what do you remember best"])


def _asker(request: Request) -> Asker:
    """The app's :class:`Asker`, made on first use from the memories the app opened."""
    state = request.app.state
    with _LOCK:
        asker: Asker | None = getattr(state, "asker", None)
        services = state.services
        if asker is None or asker.scenes is not services.scene_memory:
            asker = state.asker = Asker(services.scene_memory, services.episodes)
        return asker


def _recogniser(request: Request) -> Recogniser:
    """The app's speech recogniser, made on first use (loading the model takes ~0.2 s)."""
    state = request.app.state
    with _LOCK:
        recogniser: Recogniser | None = getattr(state, "recogniser", None)
        if recogniser is None:
            recogniser = state.recogniser = Recogniser()
        return recogniser


AskerDep = Annotated[Asker, Depends(_asker)]


@router.post(
    "/ask", summary="Ask the memory a question in words", dependencies=[Depends(require_token)]
)
def ask(body: AskRequest, asker: AskerDep) -> dict[str, Any]:
    """Answers in words, as JSON (``answer``), with the explanations behind it and the SPARQL
    it ran; a question outside the grammar gets ``understood: false`` and ``suggestions``."""
    return asker.ask(body.text).to_json()


@router.post(
    "/ask/audio",
    summary="Ask the memory a spoken question (a WAV file as the body)",
    dependencies=[Depends(require_token)],
    response_model=None,
    responses=error_responses(422, 503),
)
async def ask_audio(
    request: Request,
    asker: AskerDep,
    reply: Annotated[
        Literal["json", "wav"], Query(description="json, or the answer spoken")
    ] = "json",
) -> dict[str, Any] | Response:
    """The body is a PCM WAV recording. ``reply=json`` (default) returns what was heard and the
    answer, with the spoken reply as base64 WAV in ``speech`` and its words in ``spoken``;
    ``reply=wav`` returns only the spoken reply, with what was heard in the ``X-Engram-Heard``
    header. The spoken reply says what was heard before the answer, so that a mistaken hearing
    is heard as one."""
    wav = await request.body()
    if len(wav) > MAX_AUDIO_BYTES:
        raise InvalidValueError("body", f"{len(wav)} bytes", f"a WAV of at most {MAX_AUDIO_S:g} s")
    recogniser = await run_in_threadpool(_recogniser, request)
    heard, answer = await run_in_threadpool(asker.ask_audio, wav, recogniser)
    spoken = f"You asked: {heard.text}. {answer.words}" if heard.text else answer.words
    speech = await run_in_threadpool(synthesise, spoken)
    if reply == "wav":
        return Response(
            speech, media_type="audio/wav", headers={"X-Engram-Heard": heard.text or ""}
        )
    return {
        "heard": heard.text,
        "audio_s": heard.audio_s,
        "decode_s": heard.decode_s,
        **answer.to_json(),
        "spoken": spoken,
        "speech": base64.b64encode(speech).decode("ascii"),
    }


@router.get(
    "/explain",
    summary="Why the memory decided what it did about a class or scene",
    responses=error_responses(404, 422),
)
def explain_about(
    request: Request,
    about: Annotated[str, Query(min_length=1, max_length=2000, examples=["Scene-1"])],
) -> dict[str, Any]:
    """``about`` is a learned class, an experienced scene or something forgotten: a short name
    in Engram's namespace (``Scene-4``) or a full IRI. Unknown IRIs answer 404."""
    iri = memory_iri(about, "about")
    explanations = explain(request.app.state.services.scene_memory, iri)
    return {"about": iri.value, "explanations": [to_jsonable(e) for e in explanations]}
