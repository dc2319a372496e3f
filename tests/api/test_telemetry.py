"""FastAPI's OpenTelemetry instrumentation, on or off for the app's lifetime (api/telemetry.py):
what each setting decides, and the spans a directive request gets either way."""

import importlib.util
from collections.abc import Callable, Iterator, Mapping
from importlib.machinery import ModuleSpec
from typing import Any

import pytest
from opentelemetry import trace
from opentelemetry.util import types

import api.telemetry
from api.config import Settings
from api.telemetry import OFF, fastapi_telemetry
from tests.conftest import LiveServer


class _Span(trace.NonRecordingSpan):
    """A span that keeps its name and attributes, and says when it ended."""

    def __init__(self, name: str, attributes: Mapping[str, Any] | None) -> None:
        super().__init__(trace.INVALID_SPAN_CONTEXT)
        self.name = name
        self.attributes = dict(attributes or {})
        self.ended = False

    def update_name(self, name: str) -> None:
        self.name = name

    def set_attribute(self, key: str, value: types.AnyValue) -> None:
        self.attributes[key] = value

    def set_attributes(self, attributes: Mapping[str, types.AnyValue]) -> None:
        self.attributes.update(attributes)

    def end(self, end_time: int | None = None) -> None:
        self.ended = True


class _Tracer(trace.NoOpTracer):
    def __init__(self, spans: list[_Span]) -> None:
        self.spans = spans

    def start_span(  # type: ignore[override]
        self, name: str, *args: Any, attributes: Mapping[str, Any] | None = None, **kwargs: Any
    ) -> trace.Span:
        span = _Span(name, attributes)
        self.spans.append(span)
        return span


class _Provider(trace.TracerProvider):
    """A configured tracer provider, as an OpenTelemetry implementation would set one."""

    def __init__(self) -> None:
        self.spans: list[_Span] = []

    def get_tracer(self, *args: Any, **kwargs: Any) -> trace.Tracer:
        return _Tracer(self.spans)


@pytest.fixture
def provider(monkeypatch: pytest.MonkeyPatch) -> _Provider:
    """A tracer provider that the OpenTelemetry API hands out as the configured one."""
    configured = _Provider()
    monkeypatch.setattr(trace, "get_tracer_provider", lambda: configured)
    return configured


@pytest.fixture
def no_sdk(monkeypatch: pytest.MonkeyPatch) -> None:
    """The OpenTelemetry SDK is not installed, nor named by the environment."""
    find_spec = importlib.util.find_spec

    def without_sdk(name: str, package: str | None = None) -> ModuleSpec | None:
        return None if name == "opentelemetry.sdk" else find_spec(name, package)

    monkeypatch.setattr(api.telemetry.importlib.util, "find_spec", without_sdk)
    for name in api.telemetry._PROVIDER_VARIABLES:
        monkeypatch.delenv(name, raising=False)


def test_on_and_off_are_taken_as_said(provider: _Provider, no_sdk: None) -> None:
    assert fastapi_telemetry(Settings(telemetry="on")) is None
    assert fastapi_telemetry(Settings(telemetry="off")) == OFF


def test_auto_is_off_without_an_implementation(no_sdk: None) -> None:
    assert fastapi_telemetry(Settings(telemetry="auto")) == OFF
    assert Settings().telemetry == "auto"


def test_auto_is_on_with_the_sdk_installed(monkeypatch: pytest.MonkeyPatch) -> None:
    find_spec = importlib.util.find_spec

    def with_sdk(name: str, package: str | None = None) -> ModuleSpec | None:
        return ModuleSpec(name, None) if name == "opentelemetry.sdk" else find_spec(name, package)

    monkeypatch.setattr(api.telemetry.importlib.util, "find_spec", with_sdk)
    assert fastapi_telemetry(Settings(telemetry="auto")) is None


def test_auto_is_on_with_a_provider_configured_before(provider: _Provider, no_sdk: None) -> None:
    assert fastapi_telemetry(Settings(telemetry="auto")) is None


def test_auto_is_on_with_a_provider_named_by_the_environment(
    monkeypatch: pytest.MonkeyPatch, no_sdk: None
) -> None:
    monkeypatch.setenv("OTEL_PYTHON_TRACER_PROVIDER", "vendor_tracer_provider")
    assert fastapi_telemetry(Settings(telemetry="auto")) is None


def test_the_setting_is_validated() -> None:
    with pytest.raises(ValueError, match="telemetry"):
        Settings(telemetry="sometimes")  # type: ignore[arg-type]


DIRECTIVE = {
    "armor_request": {
        "client_name": "c",
        "reference_name": "r",
        "command": "GET",
        "primary_command_spec": "ALL",
        "secondary_command_spec": "REFS",
    }
}


@pytest.fixture
def served(start_server: Callable[..., LiveServer]) -> Iterator[Callable[[str], LiveServer]]:
    yield lambda telemetry: start_server(telemetry=telemetry)


def test_on_a_directive_request_gets_a_span_named_for_its_route(
    provider: _Provider, served: Callable[[str], LiveServer]
) -> None:
    http = served("on").client
    assert http.post("/armor_interface_srv", json=DIRECTIVE).status_code == 200
    assert http.get("/armor_interface_serialized_srv").status_code == 405
    assert http.get("/health").status_code == 200
    spans = {span.name: span for span in provider.spans}
    assert set(spans) >= {
        "POST /armor_interface_srv",
        "GET /armor_interface_serialized_srv",
        "GET /health",
    }
    directive = spans["POST /armor_interface_srv"]
    assert directive.attributes["http.route"] == "/armor_interface_srv"
    assert directive.attributes["http.response.status_code"] == 200
    assert directive.ended
    assert spans["GET /armor_interface_serialized_srv"].attributes["http.response.status_code"] == (
        405
    )


def test_off_no_span_whatever_is_configured(
    provider: _Provider, served: Callable[[str], LiveServer]
) -> None:
    http = served("off").client
    assert http.post("/armor_interface_srv", json=DIRECTIVE).status_code == 200
    assert http.get("/health").status_code == 200
    assert provider.spans == []
