"""``/docs``: the interactive API reference (Swagger UI) served from the files vendored under
``api/web/vendor/``, so that it works offline; ``/redoc`` leads there.

FastAPI's own pages load Swagger UI and ReDoc from a CDN and start them with an inline script;
this page loads only the server's files (``api/web/docs.html`` and ``docs.js``), so a strict
``script-src 'self'`` allows it.
"""

from pathlib import Path

from fastapi import FastAPI
from fastapi.responses import FileResponse, RedirectResponse
from starlette.routing import BaseRoute

__all__ = ["install"]


def _path(route: BaseRoute) -> str | None:
    return getattr(route, "path", None)


def install(app: FastAPI, page: Path) -> None:
    """Replace FastAPI's ``/docs`` and ``/redoc`` pages with the HTML file ``page`` and a
    redirect to it."""
    replaced = {app.docs_url, app.redoc_url} - {None}
    app.router.routes[:] = [r for r in app.router.routes if _path(r) not in replaced]

    async def docs() -> FileResponse:
        return FileResponse(page, media_type="text/html")

    async def redoc() -> RedirectResponse:
        return RedirectResponse("/docs")

    app.add_api_route("/docs", docs, include_in_schema=False)
    app.add_api_route("/redoc", redoc, include_in_schema=False)
