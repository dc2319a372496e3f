"""The robot-side client loads nothing of the server: ``import api.client`` in a fresh process
leaves Oxigraph, numpy, open3d, the reasoners, the store and the web framework unloaded. Of
``kg`` it loads only the primitive type (``kg.primitive``, standard library only) and the error
root it raises (``kg.errors``). The wire protocol's pydantic models (``api.protocol``, shared
with the server) load with the first directive the client builds, not at import."""

import json
import subprocess
import sys
from pathlib import Path

import pytest

CLIENT_SIDE_OF_KG = ("kg", "kg.errors", "kg.primitive")
SERVER_SIDE = ("pyoxigraph", "numpy", "open3d", "reasoners", "kg", "episodes", "shapes", "fastapi")
PROBE = """
import json, sys
import api.client
from api.client import ArmorClient, Primitive
at_import = sorted(sys.modules)
client = ArmorClient("probe", "ref", base_url="http://127.0.0.1:9")
client._request("ADD", "IND", "", ["x"])
print(json.dumps([at_import, sorted(sys.modules)]))
"""


@pytest.mark.slow
def test_importing_the_client_loads_nothing_of_the_server() -> None:
    done = subprocess.run(
        [sys.executable, "-c", PROBE],
        capture_output=True,
        text=True,
        timeout=120,
        check=True,
        cwd=Path(__file__).resolve().parents[2],
    )
    loaded, after_a_directive = json.loads(done.stdout)
    server_side = [
        m
        for m in loaded
        if (m.split(".")[0] in SERVER_SIDE and m not in CLIENT_SIDE_OF_KG) or m == "api.armor"
    ]
    assert server_side == []
    assert "pydantic" not in loaded and "api.protocol" not in loaded
    assert "api.protocol" in after_a_directive


def test_the_local_transport_is_still_reachable_on_demand() -> None:
    import api.client
    from api.client._local import LocalTransport

    assert api.client.LocalTransport is LocalTransport
    with pytest.raises(AttributeError, match="no attribute 'Nope'"):
        api.client.Nope  # noqa: B018
