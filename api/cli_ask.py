"""``engram ask``: ask the memory a question in words or in speech.

With ``--server`` it asks a running Engram over HTTP (``POST /ask``, ``POST /ask/audio``);
otherwise it opens the data directory itself (the server must not be running on it).
"""

import json
from pathlib import Path
from typing import Annotated, Any

import httpx
import typer
from rich.console import Console

from api.ask import Asker
from api.ask.speech import Recogniser, speak, synthesise
from api.config import Settings
from episodes import EpisodeMemory
from kg import EngramError, Store
from reasoners.memory import SceneMemory

__all__ = ["ask_command"]

console = Console()


def _local(text: str | None, audio: Path | None, data: Path | None) -> dict[str, Any]:
    try:
        settings = Settings(data_dir=data) if data is not None else Settings()
        store = Store(settings.store_dir)
    except (EngramError, ValueError) as error:
        console.print(f"[red]{error}[/red]")
        raise typer.Exit(1) from None
    asker = Asker(SceneMemory(store), EpisodeMemory(store, data_dir=settings.data_dir))
    if audio is None:
        return asker.ask(text or "").to_json()
    heard, answer = asker.ask_audio(audio.read_bytes(), Recogniser())
    return {"heard": heard.text, "audio_s": heard.audio_s, **answer.to_json()}


def _remote(text: str | None, audio: Path | None, server: str, token: str | None) -> dict[str, Any]:
    headers = {"Authorization": f"Bearer {token}"} if token else {}
    try:
        if audio is None:
            response = httpx.post(f"{server}/ask", json={"text": text}, headers=headers, timeout=60)
        else:
            response = httpx.post(
                f"{server}/ask/audio",
                content=audio.read_bytes(),
                headers={**headers, "Content-Type": "audio/wav"},
                timeout=120,
            )
    except httpx.HTTPError as error:
        console.print(f"[red]cannot reach {server}: {error}[/red]")
        raise typer.Exit(1) from None
    if response.status_code != 200:
        console.print(f"[red]{response.status_code}: {response.text}[/red]")
        raise typer.Exit(1)
    body: dict[str, Any] = response.json()
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
    server: Annotated[
        str | None, typer.Option(help="Ask this Engram server instead of the data directory.")
    ] = None,
    token: Annotated[
        str | None, typer.Option(envvar="ENGRAM_TOKEN", help="Bearer token for the server.")
    ] = None,
    data: Annotated[
        Path | None, typer.Option("--data", help="Data directory (default: $ENGRAM_DATA_DIR).")
    ] = None,
) -> None:
    """Ask the memory: "when did Anna last show you motor babbling?", "have you seen a cone
    behind a sphere?", "why did you forget Scene-4?". ``--audio FILE.wav`` asks in speech."""
    if (text is None) == (audio is None):
        console.print("[red]give a question, or --audio FILE.wav, but not both[/red]")
        raise typer.Exit(2)
    try:
        if server is not None:
            body = _remote(text, audio, server.rstrip("/"), token)
        else:
            body = _local(text, audio, data)
    except EngramError as error:
        console.print(f"[red]{error}[/red]")
        raise typer.Exit(1) from None
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
    if wav_out is not None:
        wav_out.write_bytes(synthesise(body["words"]))
    if say:
        speak(body["words"])
