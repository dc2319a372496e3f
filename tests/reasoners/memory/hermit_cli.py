"""HermiT's own command line (the jar shipped inside owlready2), run in a subprocess.

owlready2's ``sync_reasoner_hermit`` always classifies the whole ontology and realises every
individual; the oracle needs the cheaper questions the command line also answers: is an
ontology consistent (``-k``), does it entail the axioms of another one (``-E``), and what are the
types of its individuals (``-c -I``, kept for diagnostics and the small cross-check). Each call
is one JVM in its own process group, killed with its group when it runs out of time.
"""

import os
import re
import signal
import subprocess
from collections import defaultdict
from pathlib import Path

__all__ = ["HermitError", "entails", "is_consistent", "types"]

_LINE = re.compile(r"^(SubClassOf|EquivalentClasses|Type)\( ((?:<[^>]+>\s*)+)\)$", re.MULTILINE)
_SATISFIABLE = "http://www.w3.org/2002/07/owl#Thing is satisfiable."
_INCONSISTENT = "InconsistentOntologyException"


class HermitError(RuntimeError):
    """HermiT did not answer: Java error, unexpected output or timeout."""


def _command() -> list[str]:
    import owlready2  # imported here so that a test module can importorskip it first

    home = Path(owlready2.__file__).parent / "hermit"
    classpath = os.pathsep.join([str(home), str(home / "HermiT.jar")])
    java = getattr(owlready2, "JAVA_EXE", "java")
    memory = getattr(owlready2.reasoning, "JAVA_MEMORY", 2000)
    return [java, f"-Xmx{memory}M", "-cp", classpath, "org.semanticweb.HermiT.cli.CommandLine"]


def _run(args: list[str], timeout: float) -> tuple[int, str]:
    """Exit status and combined output of HermiT's command line with ``args``."""
    process = subprocess.Popen(
        _command() + args,
        stdout=subprocess.PIPE,
        stderr=subprocess.STDOUT,
        start_new_session=True,  # its own process group, so that a timeout kills it whole
    )
    try:
        output, _ = process.communicate(timeout=timeout)
    except subprocess.TimeoutExpired:
        os.killpg(process.pid, signal.SIGKILL)
        process.communicate()
        raise HermitError(
            f"HermiT gave no answer within {timeout:.0f} s: {' '.join(args)}"
        ) from None
    return process.returncode, output.decode("utf-8", "replace")


def is_consistent(ontology: Path, timeout: float = 300.0) -> bool:
    """Whether HermiT finds a model of ``ontology`` (its ``-k`` check of owl:Thing)."""
    status, output = _run(["-k", ontology.as_uri()], timeout)
    if status == 0 and _SATISFIABLE in output:
        return True
    if status != 0 and _INCONSISTENT in output:
        return False
    raise HermitError(f"HermiT -k on {ontology} exited {status}:\n{output[-2000:]}")


def entails(premise: Path, conclusion: Path, timeout: float = 300.0) -> bool:
    """Whether ``premise`` entails every logical axiom of ``conclusion`` (HermiT's ``-E``)."""
    status, output = _run([f"--conclusion={conclusion.as_uri()}", "-E", premise.as_uri()], timeout)
    answer = output.strip().splitlines()[-1:] if status == 0 else []
    if answer in (["true"], ["false"]):
        return answer == ["true"]
    raise HermitError(f"HermiT -E on {premise} exited {status}:\n{output[-2000:]}")


def types(ontology: Path, timeout: float = 300.0) -> dict[str, set[str]]:
    """Every named class of every named individual (IRIs), from HermiT's realisation.

    The command line prints the direct types and the transitively reduced class hierarchy;
    the indirect types are their closure.
    """
    status, output = _run(["-c", "-I", ontology.as_uri()], timeout)
    if status != 0:
        raise HermitError(f"HermiT -c -I on {ontology} exited {status}:\n{output[-2000:]}")
    parents: dict[str, set[str]] = defaultdict(set)
    direct: dict[str, set[str]] = defaultdict(set)
    for kind, iris in _LINE.findall(output):
        names = re.findall(r"<([^>]+)>", iris)
        if kind == "SubClassOf":
            parents[names[0]].add(names[1])
        elif kind == "EquivalentClasses":
            for name in names:
                parents[name].update(n for n in names if n != name)
        else:
            direct[names[0]].add(names[1])
    closed: dict[str, set[str]] = {}
    for individual, classes in direct.items():
        seen: set[str] = set()
        todo = list(classes)
        while todo:
            cls = todo.pop()
            if cls not in seen:
                seen.add(cls)
                todo.extend(parents.get(cls, ()))
        closed[individual] = seen
    return closed
