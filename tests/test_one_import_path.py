"""Each class and function has one import path: no module only repeats another module's names.

A package's ``__init__`` may gather its own submodules' names (its public face); a module that
is nothing but imports and ``__all__`` is a second path to names defined elsewhere, and a
package ``__init__`` that re-exports another package's names is one too.
"""

import ast
from pathlib import Path

ROOT = Path(__file__).parent.parent
# shapes/ is left to its own owners (its parallel paths are being removed separately).
TREES = ["api", "bench", "episodes", "kg", "ontologies", "reasoners", "sparql", "tests"]
VENDORED = "third_party"


def modules() -> list[Path]:
    return sorted(
        path
        for tree in TREES
        for path in (ROOT / tree).rglob("*.py")
        if VENDORED not in path.relative_to(ROOT).parts
    )


def only_imports_and_all(tree: ast.Module) -> bool:
    """True when the module's top level is imports and ``__all__`` (and a docstring) only."""
    body = [
        node
        for node in tree.body
        if not (isinstance(node, ast.Expr) and isinstance(node.value, ast.Constant))
    ]
    return bool(body) and all(
        isinstance(node, ast.Import | ast.ImportFrom)
        or (
            isinstance(node, ast.Assign)
            and [ast.unparse(target) for target in node.targets] == ["__all__"]
        )
        for node in body
    )


def dotted(path: Path) -> str:
    parts = path.relative_to(ROOT).with_suffix("").parts
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def test_no_module_but_a_package_init_only_re_exports() -> None:
    mirrors = [
        str(path.relative_to(ROOT))
        for path in modules()
        if path.name != "__init__.py" and only_imports_and_all(ast.parse(path.read_text()))
    ]
    assert mirrors == []


def exported(tree: ast.Module) -> set[str]:
    """The names listed in the module's ``__all__`` (none when it has no ``__all__``)."""
    for node in tree.body:
        if isinstance(node, ast.Assign) and [ast.unparse(t) for t in node.targets] == ["__all__"]:
            return {str(name) for name in ast.literal_eval(node.value)}
    return set()


def test_a_package_init_re_exports_only_its_own_submodules_names() -> None:
    foreign = []
    for path in modules():
        if path.name != "__init__.py":
            continue
        package, tree = dotted(path), ast.parse(path.read_text())
        public = exported(tree)
        for node in tree.body:
            if (
                isinstance(node, ast.ImportFrom)
                and node.module
                and node.level == 0
                and not node.module.startswith(package + ".")
            ):
                names = sorted({alias.asname or alias.name for alias in node.names} & public)
                foreign += [f"{path.relative_to(ROOT)}: {node.module}.{name}" for name in names]
    assert foreign == []
