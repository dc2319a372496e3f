"""Import the vendored armor_py_api (``armor_py_api/scripts/armor_api``) as a robot would, over
real rospy or over the stand-in that carries its calls to the HTTP API, and take it out again."""

import contextlib
import importlib
import io
import runpy
import shutil
import sys
from collections.abc import Iterator
from pathlib import Path
from types import SimpleNamespace

from pyoxigraph import RdfFormat, parse

from api.ros.messages import armor_msgs
from api.ros.system import load_ros

HERE = Path(__file__).resolve().parent
VENDORED = HERE / "armor_py_api"
"""The vendored tree: ``scripts/armor_api/`` and ``test/``."""
STAND_IN = HERE / "rospy_over_http"
"""The directory of the stand-in ``rospy``."""

_OURS = ("armor_api", "armor_client", "armor_exceptions", "armor_manipulation_client")
_OURS += ("armor_query_client", "armor_utils_client")


def _ours(name: str, *, rospy: bool) -> bool:
    top = name.split(".")[0]
    return top in _OURS or (rospy and top == "rospy")


@contextlib.contextmanager
def armor_py_api(*, stand_in: bool) -> Iterator[SimpleNamespace]:
    """armor_py_api's modules (``client``, ``exceptions``) and the ``rospy`` they imported.

    With ``stand_in``, ``rospy`` is tests/third_party/rospy_over_http; otherwise ROS's own.
    ``armor_msgs`` is generated from ARMOR's definitions (:func:`api.ros.messages.armor_msgs`).
    The modules imported here are removed from ``sys.modules`` afterwards and the ones they
    replaced (another ``rospy``) put back, so that the next user imports them afresh.
    """
    load_ros()
    armor_msgs()
    before = dict(sys.modules)
    for name in [n for n in sys.modules if _ours(n, rospy=stand_in)]:
        del sys.modules[name]
    scripts = VENDORED / "scripts"
    paths = [str(scripts), str(scripts / "armor_api")]  # armor_py_api's README, "Note2"
    if stand_in:
        paths.insert(0, str(STAND_IN))
    sys.path[:0] = paths
    try:
        rospy = importlib.import_module("rospy")
        assert (Path(rospy.__file__ or "").parent == STAND_IN) == stand_in, rospy
        yield SimpleNamespace(
            rospy=rospy,
            client=importlib.import_module("armor_api.armor_client"),
            exceptions=importlib.import_module("armor_api.armor_exceptions"),
        )
    finally:
        for path in paths:
            sys.path.remove(path)
        for name in [n for n in sys.modules if _ours(n, rospy=stand_in)]:
            del sys.modules[name]
        sys.modules.update({n: m for n, m in before.items() if _ours(n, rospy=stand_in)})


CLIENT_TEST_OUTPUT = [
    "Added ind_1 to Class_1",
    "Added ind_2 to Class_2",
    "Added ind_3 to Class_3",
    "Success! ind_1 is in Class_4 now!",
]
"""What ``client_test.py`` prints when every call answers as ARMOR's did."""


def run_client_test(directory: Path) -> tuple[list[str], Path]:
    """Run ``scripts/armor_api/client_test.py`` as a script on a copy of the vendored tree in
    ``directory`` (it saves ``test/inferred_test.owl`` beside itself, removed from the copy
    first), inside :func:`armor_py_api`; its printed lines, and the file it had saved."""
    tree = directory / "armor_py_api"
    shutil.copytree(VENDORED, tree)
    saved = tree / "test" / "inferred_test.owl"
    saved.unlink()
    printed = io.StringIO()
    with contextlib.redirect_stdout(printed):
        runpy.run_path(str(tree / "scripts" / "armor_api" / "client_test.py"), run_name="__main__")
    return printed.getvalue().splitlines(), saved


def individuals(path: Path) -> set[tuple[str, str, str]]:
    """The triples about the individuals ``ind_*`` of an ontology armor_py_api's test saved."""
    iri = "http://www.semanticweb.org/emarolab/pyarmor/test#ind_"
    return {
        (str(q.subject), str(q.predicate), str(q.object))
        for q in parse(path=path, format=RdfFormat.RDF_XML)
        if str(q.subject).startswith(f"<{iri}")
    }
