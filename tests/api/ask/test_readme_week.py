"""The README's "Asking the memory" example: its first command builds the memory its second
asks, and the answer is the one the README shows."""

import gc
import re
import shlex
from pathlib import Path

from api.ask import Asker
from api.ask.samples import main
from episodes import EpisodeMemory
from kg import Store
from reasoners.memory import SceneMemory

README = (Path(__file__).resolve().parents[3] / "README.md").read_text(encoding="utf-8")


def test_the_readme_builds_the_week_it_asks(tmp_path: Path) -> None:
    section = README.split("## Asking the memory", 1)[1]
    block = re.search(r"```sh\n(.*?)```", section, flags=re.DOTALL)
    assert block is not None
    build, ask = (shlex.split(line.split("#")[0]) for line in block.group(1).splitlines()[:2])
    assert build[:3] == ["python", "-m", "api.ask.samples"]
    assert ask[:3] == ["engram", "ask", "--data"] and ask[3] == build[3]
    data = tmp_path / build[3]
    assert main([str(data)]) == 0
    assert main([str(data)]) == 2  # a directory that holds a store is refused
    store = Store(data / "store")
    answer = Asker(SceneMemory(store), EpisodeMemory(store)).ask(ask[4])
    shown = re.search(r"the second then prints:\n\n```text\n(.*?)\n```", section, re.DOTALL)
    assert shown is not None and answer.words == shown.group(1)
    del answer, store
    gc.collect()
