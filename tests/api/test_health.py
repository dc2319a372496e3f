"""``/health`` answers from what the server holds in memory, never from the store."""

from pathlib import Path

import httpx
import pytest

from api.config import Settings
from api.main import create_app
from kg import stored_version
from tests.conftest import free_port, serve

pytestmark = pytest.mark.slow


def test_health_reads_nothing_from_the_store_and_reports_its_state(tmp_path: Path) -> None:
    settings = Settings(host="127.0.0.1", port=free_port(), data_dir=tmp_path / "data")
    app = create_app(settings)
    with serve(app, settings) as running:
        store = app.state.services.store
        version = stored_version(store)
        assert version is not None
        reads: list[str] = []
        with httpx.Client(base_url=running.url, timeout=60) as client:
            with store.tracing(lambda kind, text, _: reads.append(text)):
                body = client.get("/health").json()
            assert reads == []
            assert body["ontology_version"] == version.value
            assert body["transactions"] == store.generation
