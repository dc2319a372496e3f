"""``engram serve --ros``: the HTTP server and the ROS node in one process, on one engine, so
that HTTP, SPARQL and the web views see what ROS clients write."""

from collections.abc import AsyncIterator
from contextlib import asynccontextmanager
from typing import Any

from fastapi import FastAPI
from starlette.concurrency import run_in_threadpool

from api.ros.node_options import RosOptions
from api.ros.system import load_ros

__all__ = ["add_ros"]


def add_ros(app: FastAPI, options: RosOptions) -> FastAPI:
    """Start the ROS node on the app's engine once the app has started; stop it before the
    app stops. Raises :class:`~api.ros.system.RosUnavailableError` without ROS's modules."""
    load_ros()
    serving = app.router.lifespan_context

    @asynccontextmanager
    async def lifespan(started: Any) -> AsyncIterator[Any]:
        from api.ros.running import RunningNode

        async with serving(started) as state:
            node = RunningNode(started.state.services.armor, options, signals=False)
            try:
                yield state
            finally:
                await run_in_threadpool(node.stop)

    app.router.lifespan_context = lifespan
    return app
