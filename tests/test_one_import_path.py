"""Each class and function has one import path: no module only repeats another module's names.

A package's ``__init__`` may gather its own submodules' names (its public face); a module that
is nothing but imports and ``__all__`` is a second path to names defined elsewhere, a
package ``__init__`` that re-exports another package's names is one too, and so is a module
whose ``__all__`` lists a name it imported.
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


PACKAGES = ["api", "bench", "episodes", "kg", "ontologies", "reasoners", "sparql"]
CLIENT_PRIMITIVE = {"api/client/__init__.py: Primitive", "api/client/_memory.py: Primitive"}
"""The one name kept on a second path on purpose: robot programs build their primitives with
``from api.client import Primitive`` (the README), and the client's modules import only what
a robot needs."""


def top_level(tree: ast.Module) -> list[ast.stmt]:
    """The module's statements, those under a top-level ``if`` (``TYPE_CHECKING``) too."""
    return [
        inner
        for node in tree.body
        for inner in ([node, *node.body, *node.orelse] if isinstance(node, ast.If) else [node])
    ]


def defined(tree: ast.Module) -> set[str]:
    """The names a module's top level binds other than by importing them from another module
    (a module imported whole counts as the module's own name for it)."""
    names: set[str] = set()
    for node in top_level(tree):
        if isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef | ast.ClassDef):
            names.add(node.name)
        elif isinstance(node, ast.Import):
            names |= {alias.asname or alias.name.split(".")[0] for alias in node.names}
        elif isinstance(node, ast.Assign | ast.AnnAssign):
            targets = node.targets if isinstance(node, ast.Assign) else [node.target]
            names |= {
                n.id for target in targets for n in ast.walk(target) if isinstance(n, ast.Name)
            }
    return names


def test_a_module_exports_only_the_names_it_defines() -> None:
    """``__all__`` lists what the module defines; a package ``__init__`` may list too what its
    own submodules define, so that each name is found where it is defined or at its package."""
    trees = {
        dotted(path): (path, ast.parse(path.read_text()))
        for path in modules()
        if path.relative_to(ROOT).parts[0] in PACKAGES
    }

    def owns(module: str, name: str) -> bool:
        path, tree = trees[module]
        if name in defined(tree):
            return True
        return path.name == "__init__.py" and any(
            isinstance(node, ast.ImportFrom)
            and node.level == 0
            and (node.module or "").startswith(module + ".")
            and node.module in trees
            and name in {alias.asname or alias.name for alias in node.names}
            and owns(node.module, name)
            for node in top_level(tree)
        )

    borrowed = [
        f"{path.relative_to(ROOT)}: {name}"
        for module, (path, tree) in trees.items()
        for name in sorted(exported(tree))
        if not owns(module, name)
    ]
    assert sorted(set(borrowed) - CLIENT_PRIMITIVE) == []
