"""The ``engram`` command line, run in-process with typer's runner."""

from pathlib import Path

import pytest
import rdflib
from typer.testing import CliRunner

from api.cli import app

runner = CliRunner()


def memory_in(data: Path) -> Path:
    """``data`` with an empty memory in it, as ``engram init`` makes one."""
    made = runner.invoke(app, ["init", "--data", str(data)])
    assert made.exit_code == 0, made.output
    return data


@pytest.mark.parametrize(("format", "parser"), [("rdfxml", "xml"), ("turtle", "turtle")])
def test_export_writes_a_parseable_ontology(tmp_path: Path, format: str, parser: str) -> None:
    target = tmp_path / "engram.owl"
    result = runner.invoke(
        app, ["export", "--data", str(memory_in(tmp_path)), "--format", format, "-o", str(target)]
    )
    assert result.exit_code == 0, result.output
    graph = rdflib.Graph().parse(target, format=parser)
    assert len(list(graph.subjects(rdflib.RDF.type, rdflib.OWL.Ontology))) == 1


@pytest.mark.parametrize(
    ("arguments", "fragment"),
    [
        (["--format", "jsonld"], "jsonld"),
        (["--graphs", "tbox,nonsense"], "nonsense"),
    ],
)
def test_export_refuses_bad_options(tmp_path: Path, arguments: list[str], fragment: str) -> None:
    target = tmp_path / "out.owl"
    data = str(memory_in(tmp_path))
    result = runner.invoke(app, ["export", "--data", data, "-o", str(target), *arguments])
    assert result.exit_code == 2
    assert fragment in result.output
    assert not target.exists()


def test_backup_copies_the_store(tmp_path: Path) -> None:
    target = tmp_path / "copy"
    memory_in(tmp_path / "data")
    result = runner.invoke(app, ["backup", str(target), "--data", str(tmp_path / "data")])
    assert result.exit_code == 0, result.output
    assert target.is_dir()
    again = runner.invoke(app, ["backup", str(target), "--data", str(tmp_path / "data")])
    assert again.exit_code == 1
    assert "already exists" in again.output
