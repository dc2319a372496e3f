"""Whether FastAPI's own OpenTelemetry instrumentation runs, decided once when the app is built.

FastAPI asks on every request whether an OpenTelemetry tracer, meter or logger provider has been
configured, and records spans, metrics and logs if one has. The OpenTelemetry API that FastAPI
depends on has no provider that records anything: one comes from an implementation (the
OpenTelemetry SDK, which ``opentelemetry-instrument`` and FastAPI's automatic set-up use, or a
vendor's) that the process configures. :func:`fastapi_telemetry` turns FastAPI's instrumentation
on or off for the app's lifetime from ``Settings.telemetry`` (``ENGRAM_TELEMETRY``):

- ``on``: FastAPI's default, its check on every request;
- ``off``: no spans, metrics or logs from FastAPI, whatever is configured;
- ``auto`` (the default): on if the OpenTelemetry SDK is installed, or a provider is already
  configured when the app is built (an instrumentation that sets its own at start-up), else off.
  A process that configures a provider of another implementation only after building the app
  sets ``on``.
"""

import importlib.util
import os

from fastapi.telemetry import TelemetryConfig
from opentelemetry import _logs, metrics, trace

from api.config import Settings

__all__ = ["OFF", "fastapi_telemetry"]

OFF: TelemetryConfig = {"tracing": False, "metrics": False, "logs": False}
"""FastAPI's ``telemetry=`` argument that records nothing."""

_PROVIDER_VARIABLES = (
    "OTEL_PYTHON_TRACER_PROVIDER",
    "OTEL_PYTHON_METER_PROVIDER",
    "OTEL_PYTHON_LOGGER_PROVIDER",
)
"""Environment variables naming a provider that the OpenTelemetry API loads on first use."""
_UNCONFIGURED = {
    ("opentelemetry.trace", "ProxyTracerProvider"),
    ("opentelemetry.metrics._internal", "_ProxyMeterProvider"),
    ("opentelemetry._logs._internal", "ProxyLoggerProvider"),
}
"""The stand-ins the OpenTelemetry API gives while no provider is configured."""


def fastapi_telemetry(settings: Settings) -> TelemetryConfig | None:
    """FastAPI's ``telemetry=`` argument for ``settings.telemetry``: None (FastAPI's defaults)
    when its instrumentation is to run, :data:`OFF` otherwise (see the module docstring).

    >>> fastapi_telemetry(Settings(telemetry="off")) == OFF
    True
    >>> fastapi_telemetry(Settings(telemetry="on")) is None
    True
    """
    if settings.telemetry == "on" or (settings.telemetry == "auto" and _implementation_present()):
        return None
    return OFF


def _implementation_present() -> bool:
    """True if the OpenTelemetry SDK is installed, a provider is configured already, or the
    environment names one."""
    if importlib.util.find_spec("opentelemetry.sdk") is not None:
        return True
    if any(os.environ.get(name) for name in _PROVIDER_VARIABLES):
        return True
    providers = (
        trace.get_tracer_provider(),
        metrics.get_meter_provider(),
        _logs.get_logger_provider(),
    )
    return any((type(p).__module__, type(p).__name__) not in _UNCONFIGURED for p in providers)
