"""The live-server fixtures (``start_server``, ``live_server``) are in ``tests/conftest.py``."""

from tests.conftest import LiveServer

__all__ = ["LiveServer"]
