"""shapes.segment's modules import one way: each only from those before it in the package's
list of its steps (the module map in its docstring and in docs/architecture.md)."""

import ast
import importlib
import re
from pathlib import Path

SEGMENT = importlib.import_module("shapes.segment")
PACKAGE = Path(SEGMENT.__file__ or "").parent
ORDER = re.findall(r"^- :mod:`shapes\.segment\.(\w+)`", SEGMENT.__doc__ or "", re.M)


def imported_siblings(module: str) -> set[str]:
    tree = ast.parse((PACKAGE / f"{module}.py").read_text())
    return {
        node.module.split(".")[2]
        for node in ast.walk(tree)
        if isinstance(node, ast.ImportFrom)
        and node.module is not None
        and node.module.startswith("shapes.segment.")
    }


def test_the_module_map_lists_every_module_of_the_package_once():
    on_disk = sorted(p.stem for p in PACKAGE.glob("*.py") if p.stem != "__init__")
    assert sorted(ORDER) == on_disk


def test_each_module_imports_only_the_modules_listed_before_it():
    later = {
        module: sorted(imported_siblings(module) - set(ORDER[:k])) for k, module in enumerate(ORDER)
    }
    assert later == {module: [] for module in ORDER}


def test_the_name_segment_in_shapes_is_the_package_not_its_function():
    import shapes

    assert shapes.segment is SEGMENT
