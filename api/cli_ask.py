"""``engram ask``: ask the memory a question in words or in speech.

It opens the data directory, or asks the server that holds it (or ``--server``) over HTTP
(``POST /ask``, ``POST /ask/audio``).
"""

import json
from pathlib import Path
from typing import TYPE_CHECKING, Annotated, Any

import typer
from rich.console import Console

from api.cli_common import DataOption, ServerOption, TokenOption, call, fail, reach, settings_for

if TYPE_CHECKING:
    import httpx

    from api.services import Services

__all__ = ["ask_command"]

console = Console()


def _local(services: "Services", text: str | None, audio: Path | None) -> dict[str, Any]:
    from api.ask import Asker

    asker = Asker(services.scene_memory, services.episodes)
    if audio is None:
        return asker.ask(text or "").to_json()
    from api.ask.speech import Recogniser

    heard, answer = asker.ask_audio(audio.read_bytes(), Recogniser())
    return {"heard": heard.text, "audio_s": heard.audio_s, **answer.to_json()}


def _remote(client: "httpx.Client", text: str | None, audio: Path | None) -> dict[str, Any]:
    if audio is None:
        body: dict[str, Any] = call(client, "POST", "/ask", json={"text": text})
    else:
        body = call(
            client,
            "POST",
            "/ask/audio",
            content=audio.read_bytes(),
            headers={"Content-Type": "audio/wav"},
        )
    body.pop("speech", None)
    return body


def ask_command(
    text: Annotated[str | None, typer.Argument(help="The question, in words.")] = None,
    audio: Annotated[
        Path | None,
        typer.Option(exists=True, dir_okay=False, help="A WAV recording of the question."),
    ] = None,
    say: Annotated[bool, typer.Option(help="Speak the answer (espeak-ng).")] = False,
    wav_out: Annotated[
        Path | None, typer.Option(help="Write the spoken answer to this WAV file.")
    ] = None,
    as_json: Annotated[
        bool, typer.Option("--json", help="Print the whole answer as JSON.")
    ] = False,
    sparql: Annotated[bool, typer.Option(help="Print the SPARQL the answer ran.")] = False,
    server: ServerOption = None,
    token: TokenOption = None,
    data: DataOption = None,
) -> None:
    """Ask the memory: "when did Anna last show you motor babbling?", "have you seen a cone
    behind a sphere?", "why did you forget Scene-4?". ``--audio FILE.wav`` asks in speech."""
    from api.services import Services
    from kg import EngramError

    if (text is None) == (audio is None):
        fail("give a question, or --audio FILE.wav, but not both", 2)
    with reach(settings_for(data), server, token) as memory:
        try:
            if isinstance(memory, Services):
                body = _local(memory, text, audio)
            else:
                body = _remote(memory, text, audio)
        except EngramError as error:
            fail(str(error), 1)
    if as_json:
        print(json.dumps(body, indent=2))
    else:
        if body.get("heard") is not None:
            console.print(f"[dim]heard: {body['heard']}[/dim]")
        print(body["words"])
        for explanation in body.get("explanations", []):
            if explanation["words"] not in body["words"]:
                print(f"  because: {explanation['words']}")
        if sparql:
            for query in body.get("sparql", []):
                print(query)
    if wav_out is not None or say:
        from api.ask.speech import speak, synthesise

        if wav_out is not None:
            wav_out.write_bytes(synthesise(body["words"]))
        if say:
            speak(body["words"])
