"""Schemathesis over the whole OpenAPI description against a real server: no request it can
generate gets a 5xx, and every status it gets is one the description documents.

Bounded for the test suite: ``ENGRAM_FUZZ_EXAMPLES`` examples per operation (default 6, a few
hundred requests in all), derandomised so every run sends the same requests. A longer hunt::

    ENGRAM_FUZZ_EXAMPLES=200 .venv/bin/python -m pytest tests/api/test_openapi_fuzz.py
"""

import os
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest
import schemathesis
from hypothesis import HealthCheck, Phase, given, settings
from schemathesis.checks import not_a_server_error
from schemathesis.specs.openapi.checks import status_code_conformance

from tests.api.armor.conftest import start_live_server

EXAMPLES = int(os.environ.get("ENGRAM_FUZZ_EXAMPLES", "6"))


@pytest.fixture(scope="module")
def live_schema(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Any]:
    data: Path = tmp_path_factory.mktemp("fuzz")
    with start_live_server(data, sparql_timeout_s=2.0) as running:
        yield schemathesis.openapi.from_url(running.url + "/openapi.json")


def _fuzz(operation: Any) -> str | None:
    """Run the operation's examples; the first failure's report, or None."""

    @given(case=operation.as_strategy())
    @settings(
        max_examples=EXAMPLES,
        derandomize=True,
        deadline=None,
        phases=[Phase.explicit, Phase.generate],
        suppress_health_check=list(HealthCheck),
        database=None,
    )
    def run(case: Any) -> None:
        case.call_and_validate(checks=[not_a_server_error, status_code_conformance])

    try:
        run()
    except (KeyboardInterrupt, SystemExit):
        raise
    except BaseException as error:  # schemathesis reports failures as an exception group
        return f"{operation.label}: {error}"
    return None


@pytest.mark.slow
def test_no_request_gets_a_server_error_or_an_undocumented_status(live_schema: Any) -> None:
    operations = [result.ok() for result in live_schema.get_all_operations()]
    assert len(operations) > 30
    failures = [f for f in map(_fuzz, operations) if f is not None]
    assert failures == [], "\n\n".join(failures)
