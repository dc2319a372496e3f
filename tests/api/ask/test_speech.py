"""Speech round trip: each sample question spoken by espeak-ng, heard by pocketsphinx, answered."""

import io
import wave

import numpy as np
import pytest

from api.ask import Asker, parse
from api.ask.grammar import Parsed, parse_thing
from api.ask.samples import SPOKEN
from api.ask.speech import Recogniser, pcm16k, pronounce, synthesise
from kg.errors import InvalidInputError

pytestmark = pytest.mark.slow  # espeak-ng runs as a process for each question


@pytest.fixture(scope="module")
def recogniser() -> Recogniser:
    return Recogniser()


def meaning(parsed: Parsed | None) -> tuple[str, dict[str, object]] | None:
    """The form and slots, with names in one case and things as relation triples: "the ball on
    a table" means what "a ball on a table" means."""
    if parsed is None:
        return None
    slots: dict[str, object] = {k: v.lower() for k, v in parsed.slots.items()}
    if "thing" in slots:
        slots["thing"] = parse_thing(parsed.slots["thing"])
    return parsed.form, slots


@pytest.mark.parametrize("question", SPOKEN)
def test_a_spoken_question_is_heard_and_answered(
    asker: Asker, recogniser: Recogniser, question: str
) -> None:
    heard, answer = asker.ask_audio(synthesise(question), recogniser)
    # audio_s is the clip's length (the audio read whole), not a timing.
    assert heard.text is not None and heard.audio_s > 0.5
    assert meaning(parse(heard.text)) == meaning(parse(question))
    assert answer.understood and answer.form == parse(question).form  # type: ignore[union-attr]


def test_silence_is_not_a_question(asker: Asker, recogniser: Recogniser) -> None:
    buffer = io.BytesIO()
    with wave.open(buffer, "wb") as writer:
        writer.setnchannels(1)
        writer.setsampwidth(2)
        writer.setframerate(16000)
        writer.writeframes(np.zeros(16000, dtype=np.int16).tobytes())
    _, answer = asker.ask_audio(buffer.getvalue(), recogniser)
    assert not answer.understood
    assert answer.words.startswith("I did not hear a question I understand.")


def test_names_outside_the_dictionary_get_a_pronunciation() -> None:
    assert pronounce("hyungjin") == "HH Y UW NG JH IH N"


def test_audio_is_mixed_resampled_and_trimmed() -> None:
    rate = 44100
    tone = (np.sin(np.arange(rate // 2) * 2 * np.pi * 440 / rate) * 8000).astype(np.int16)
    silence = np.zeros(rate, dtype=np.int16)
    mono = np.concatenate([silence, tone, silence])
    buffer = io.BytesIO()
    with wave.open(buffer, "wb") as writer:
        writer.setnchannels(2)
        writer.setsampwidth(2)
        writer.setframerate(rate)
        writer.writeframes(np.repeat(mono, 2).tobytes())
    samples = pcm16k(buffer.getvalue())
    assert 0.5 <= samples.size / 16000 <= 0.65  # the tone and 50 ms on each side


@pytest.mark.parametrize(
    ("data", "fragment"),
    [(b"", "a PCM WAV file"), (b"RIFF0000WAVEjunk", "a PCM WAV file"), (b"not audio", "PCM")],
)
def test_what_is_not_a_wav_is_refused(data: bytes, fragment: str) -> None:
    with pytest.raises(InvalidInputError, match=fragment):
        pcm16k(data)
