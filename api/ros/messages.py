"""``armor_msgs`` for Python, generated with genpy from ARMOR's own definitions.

``api/ros/armor_msgs/`` declares ARMOR's interface, field for field as ARMOR's ``.msg`` and
``.srv`` files do (see its README), so the md5sums that ROS compares when a client connects are
ARMOR's. :func:`armor_msgs` generates the Python classes into a temporary directory once per
process and imports them as the package ``armor_msgs``, which is what ARMOR's Python clients
import too. Call :func:`api.ros.system.load_ros` first.
"""

import atexit
import functools
import importlib
import shutil
import sys
import tempfile
from pathlib import Path
from types import ModuleType
from typing import Any, NamedTuple

__all__ = ["DEFINITIONS", "ArmorMsgs", "armor_msgs", "md5sums_of_definitions"]

DEFINITIONS = Path(__file__).parent / "armor_msgs"
"""ARMOR's ``msg/`` and ``srv/`` directories (and their licence)."""

PACKAGE = "armor_msgs"


class ArmorMsgs(NamedTuple):
    """The imported ``armor_msgs.msg`` and ``armor_msgs.srv`` modules."""

    msg: ModuleType
    srv: ModuleType


def _files(kind: str) -> list[str]:
    return sorted(str(p) for p in (DEFINITIONS / kind).glob(f"*.{kind}"))


def md5sums_of_definitions() -> dict[str, str]:
    """Type name -> md5sum, as genmsg computes them from the definition files (the values ROS
    compares with a client's)."""
    import genmsg.gentools
    import genmsg.msg_loader

    search_path = {PACKAGE: [str(DEFINITIONS / "msg")]}
    sums = {}
    for kind, load in (
        ("msg", genmsg.msg_loader.load_msg_from_file),
        ("srv", genmsg.msg_loader.load_srv_from_file),
    ):
        for path in _files(kind):
            context = genmsg.msg_loader.MsgContext.create_default()
            name = f"{PACKAGE}/{Path(path).stem}"
            spec: Any = load(context, path, name)
            genmsg.msg_loader.load_depends(context, spec, search_path)
            sums[name] = genmsg.gentools.compute_md5(context, spec)
    return sums


def _generate(target: Path) -> None:
    import genpy.generate_initpy
    import genpy.generator

    search_path = {PACKAGE: [str(DEFINITIONS / "msg")]}
    root = target / PACKAGE
    for kind, generator in (
        ("msg", genpy.generator.MsgGenerator()),
        ("srv", genpy.generator.SrvGenerator()),
    ):
        if generator.generate_messages(PACKAGE, _files(kind), str(root / kind), search_path):
            raise RuntimeError(f"genpy could not generate {PACKAGE}/{kind} from {DEFINITIONS}")
        genpy.generate_initpy.write_modules(str(root / kind))
    (root / "__init__.py").write_text("")


@functools.cache
def armor_msgs() -> ArmorMsgs:
    """The ``armor_msgs`` modules: an installed ``armor_msgs`` (an ARMOR workspace on the path)
    if its md5sums equal ARMOR's, otherwise classes generated from ``DEFINITIONS``.

    Raises RuntimeError if an installed ``armor_msgs`` differs from ARMOR's definitions.
    """
    try:
        msg, srv = (importlib.import_module(f"{PACKAGE}.{kind}") for kind in ("msg", "srv"))
    except ImportError:
        target = Path(tempfile.mkdtemp(prefix="engram-armor-msgs-"))
        atexit.register(shutil.rmtree, target, True)
        _generate(target)
        sys.path.insert(0, str(target))
        sys.modules.pop(PACKAGE, None)
        msg, srv = (importlib.import_module(f"{PACKAGE}.{kind}") for kind in ("msg", "srv"))
    expected = md5sums_of_definitions()
    found = {
        f"{PACKAGE}/{name}": getattr(module, name)._md5sum
        for module in (msg, srv)
        for name in (n.rsplit("/", 1)[1] for n in expected)
        if hasattr(module, name)
    }
    if found != expected:
        raise RuntimeError(
            f"{PACKAGE} at {Path(msg.__file__ or '?').parent.parent}: md5sums {found}, "
            f"expected ARMOR's {expected}"
        )
    return ArmorMsgs(msg, srv)
