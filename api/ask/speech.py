# ruff: noqa: RUF001 (the IPA symbols are meant)
"""Speech, offline: questions heard by pocketsphinx constrained by the question grammar, answers
spoken by espeak-ng.

The recogniser decodes with PyPI ``pocketsphinx``'s bundled US English acoustic model and
dictionary against a JSGF grammar made from :data:`api.ask.grammar.FORMS` with the memory's
own names in the slots (:func:`api.ask.grammar.jsgf`), so it can only hear questions the
grammar parses. Names missing from the dictionary ("HyungJin") get a pronunciation from
espeak-ng's phonemes. Audio is any PCM WAV; it is mixed to mono, resampled to 16 kHz and
trimmed of leading and trailing silence.

Raises :class:`SpeechUnavailableError` when espeak-ng or pocketsphinx is missing, and
``kg.errors.InvalidValueError`` for audio that is not a readable PCM WAV.
"""

import functools
import io
import logging
import shutil
import subprocess
import threading
import time
import wave
from dataclasses import dataclass
from importlib.resources import files
from typing import Any

import numpy as np
from numpy.typing import NDArray
from scipy.signal import resample_poly

from api.ask.errors import SpeechUnavailableError
from api.ask.grammar import jsgf
from api.ask.vocabulary import Names
from kg.errors import InvalidValueError

__all__ = [
    "Heard",
    "Recogniser",
    "pcm16k",
    "pronounce",
    "speak",
    "synthesise",
]

log = logging.getLogger(__name__)

RATE = 16_000
VOICE = "en-us"
MAX_AUDIO_S = 30.0


def _espeak() -> str:
    binary = shutil.which("espeak-ng")
    if binary is None:
        raise SpeechUnavailableError(
            "speech: espeak-ng is not installed (the Debian package espeak-ng; scripts/test "
            "installs it)"
        )
    return binary


def synthesise(text: str, *, voice: str = VOICE, words_per_minute: int = 160) -> bytes:
    """``text`` spoken by espeak-ng, as WAV bytes (22,050 Hz mono)."""
    result = subprocess.run(
        [_espeak(), "-v", voice, "-s", str(words_per_minute), "--stdout", text],
        capture_output=True,
        check=True,
        timeout=60,
    )
    return result.stdout


def speak(text: str, *, voice: str = VOICE) -> None:
    """Say ``text`` aloud on the machine's audio output with espeak-ng."""
    subprocess.run([_espeak(), "-v", voice, text], check=False, timeout=120)


def pcm16k(wav: bytes) -> NDArray[np.int16]:
    """The WAV's samples as 16 kHz mono 16-bit, with leading and trailing silence trimmed."""
    try:
        with wave.open(io.BytesIO(wav)) as reader:
            rate, channels = reader.getframerate(), reader.getnchannels()
            width = reader.getsampwidth()
            # a streamed WAV (espeak-ng --stdout) says it is 2**31 frames long: read what is there
            raw = reader.readframes(int(MAX_AUDIO_S * rate) + 1)
    except (wave.Error, EOFError) as error:
        raise InvalidValueError("audio", f"{len(wav)} bytes", f"a PCM WAV file ({error})") from None
    if width not in (1, 2, 4) or rate < 4000 or channels < 1:
        raise InvalidValueError(
            "audio", f"{width * 8}-bit, {rate} Hz", "8, 16 or 32-bit PCM at 4 kHz or more"
        )
    frames = len(raw) // max(width * channels, 1)
    if frames / rate > MAX_AUDIO_S:
        raise InvalidValueError("audio", f"{frames / rate:.1f} s", f"at most {MAX_AUDIO_S:g} s")
    kind = {1: np.uint8, 2: np.int16, 4: np.int32}[width]
    samples = np.frombuffer(raw[: frames * width * channels], dtype=kind).astype(np.float64)
    if width == 1:
        samples = (samples - 128) * 256
    elif width == 4:
        samples /= 65536
    if samples.size == 0:
        raise InvalidValueError("audio", "0 samples", "a recording of a spoken question")
    samples = samples.reshape(-1, channels).mean(axis=1)
    if rate != RATE:
        g = np.gcd(rate, RATE)
        samples = resample_poly(samples, RATE // g, rate // g)
    return _trim(np.clip(samples, -32768, 32767).astype(np.int16))


def _trim(samples: NDArray[np.int16], frame: int = 160) -> NDArray[np.int16]:
    """Cut silence (frames under 2 % of the loudest frame's energy) at both ends, keeping 50 ms."""
    count = samples.size // frame
    if count < 3:
        return samples
    energy = np.sqrt(
        (samples[: count * frame].astype(np.float64).reshape(count, frame) ** 2).mean(1)
    )
    loud = np.flatnonzero(energy > 0.02 * energy.max())
    if loud.size == 0:
        return samples
    start = max(int(loud[0]) - 5, 0) * frame
    end = min((int(loud[-1]) + 6) * frame, samples.size)
    return samples[start:end]


# Pronunciations -------------------------------------------------------------------------------

_IPA = {
    "tʃ": "CH", "dʒ": "JH", "aɪ": "AY", "aʊ": "AW", "ɔɪ": "OY", "eɪ": "EY", "oʊ": "OW",
    "əʊ": "OW", "ɜː": "ER", "ɚ": "ER", "ɝ": "ER", "iː": "IY", "uː": "UW", "ɑː": "AA",
    "ɔː": "AO", "ɪə": "IH R", "eə": "EH R", "ʊə": "UH R",
    "p": "P", "b": "B", "t": "T", "d": "D", "k": "K", "g": "G", "ɡ": "G", "f": "F", "v": "V",
    "θ": "TH", "ð": "DH", "s": "S", "z": "Z", "ʃ": "SH", "ʒ": "ZH", "h": "HH", "m": "M",
    "n": "N", "ŋ": "NG", "l": "L", "ɫ": "L", "ɹ": "R", "r": "R", "j": "Y", "w": "W", "i": "IY",
    "ɪ": "IH", "e": "EH", "ɛ": "EH", "æ": "AE", "a": "AA", "ɑ": "AA", "ɒ": "AA", "ɔ": "AO",
    "o": "OW", "ʊ": "UH", "u": "UW", "ʌ": "AH", "ə": "AH", "ᵻ": "IH", "ɐ": "AH", "ɾ": "T",
    "x": "HH", "ʔ": "",
}  # fmt: skip
"""espeak-ng's IPA for US English -> the CMU dictionary's ARPAbet phones."""


def pronounce(word: str) -> str | None:
    """ARPAbet phones for ``word`` from espeak-ng's IPA, or None when a phoneme has no match."""
    ipa = subprocess.run(
        [_espeak(), "-q", "--ipa", "-v", VOICE, word], capture_output=True, text=True, timeout=30
    ).stdout
    ipa = "".join(c for c in ipa.strip() if c not in "ˈˌ_ \n‍")
    phones: list[str] = []
    position = 0
    while position < len(ipa):
        for size in (2, 1):
            part = ipa[position : position + size]
            if part in _IPA:
                if _IPA[part]:
                    phones.append(_IPA[part])
                position += size
                break
        else:
            if ipa[position] == "ː":
                position += 1
                continue
            return None
    return " ".join(phones) or None


@functools.cache
def _dictionary() -> frozenset[str]:
    """The words of pocketsphinx's bundled dictionary."""
    path = files("pocketsphinx").joinpath("model", "en-us", "cmudict-en-us.dict")
    words = set()
    with path.open(encoding="utf-8") as handle:
        for line in handle:
            head = line.split(" ", 1)[0]
            words.add(head.split("(", 1)[0])
    return frozenset(words)


# Recognition ----------------------------------------------------------------------------------


@dataclass(frozen=True)
class Heard:
    """What the recogniser heard, how long the audio was and how long decoding took."""

    text: str | None
    audio_s: float
    decode_s: float


class Recogniser:
    """A pocketsphinx decoder that hears only the question grammar, with the given names.

    The decoder is made once (about 0.2 s); the grammar is swapped when the names change.
    """

    def __init__(self) -> None:
        try:
            from pocketsphinx import Decoder  # type: ignore[import-untyped]
        except ImportError as error:  # pragma: no cover - the dependency is pinned
            raise SpeechUnavailableError(
                f"speech: pocketsphinx cannot be imported: {error}"
            ) from None
        # No filler words inside the grammar: espeak-ng's pauses were heard as noise that
        # broke the grammar's final state (measured: 6 of 6 forms heard without, 2-4 with).
        self._decoder: Any = Decoder(jsgf=None, lm=None, loglevel="FATAL", fsgusefiller=False)
        self._lock = threading.Lock()
        self._names: Names | None = None
        self._added: set[str] = set()
        self._grammars = 0

    def _use(self, names: Names) -> None:
        if names == self._names:
            return
        known = set(_dictionary())
        for name in (*names.participants, *names.activities):
            for word in name.lower().replace("-", " ").split():
                if word.isalpha() and word not in known and word not in self._added:
                    phones = pronounce(word)
                    if phones is not None:
                        self._decoder.add_word(word, phones, True)
                        self._added.add(word)
        known |= self._added
        self._grammars += 1
        name = f"ask{self._grammars}"
        self._decoder.add_jsgf_string(name, jsgf(names, known=known))
        self._decoder.activate_search(name)
        self._names = names

    def hear(self, wav: bytes, names: Names) -> Heard:
        """The question in ``wav`` as words of the grammar, or ``text=None`` if none fitted."""
        samples = pcm16k(wav)
        with self._lock:
            self._use(names)
            started = time.perf_counter()
            decoder = self._decoder
            decoder.start_utt()
            decoder.process_raw(samples.tobytes(), full_utt=True)
            decoder.end_utt()
            hypothesis = decoder.hyp()
            decode_s = time.perf_counter() - started
        text = hypothesis.hypstr.strip() if hypothesis is not None else ""
        log.info("heard %r in %.2f s of audio", text, samples.size / RATE)
        return Heard(text or None, samples.size / RATE, decode_s)
