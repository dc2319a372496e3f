"""A short conversation with a memory: questions chosen from what it holds, answers printed
with the explanations behind them (the demo ends with one)."""

from rich.console import Console

from api.ask.asker import Asker
from reasoners.labels import local

__all__ = ["questions_for", "talk"]


def questions_for(asker: Asker, *, agent: str, activity: str) -> list[str]:
    """Questions of each kind about what ``asker``'s memories hold: an episode of ``agent``
    doing ``activity``, the best-remembered scenes, something forgotten (or the first class),
    a class and its parent, and the last scene."""
    scenes = asker.scenes
    questions = [
        f"When did {agent} last show you {activity}?",
        "What do you remember best?",
        "What did you forget this week?",
    ]
    trash = scenes.reads.trash()  # forgotten classes first, then forgotten scenes
    classes = scenes.reads.classes()
    if trash or classes:
        questions.append(f"Why did you forget {local(trash[0] if trash else classes[0].iri)}?")
    child = next((c for c in classes if c.parents), None)
    if child is not None:
        questions.append(f"Why is {local(child.iri)} a kind of {local(child.parents[0])}?")
    questions.append("Why did you not recognise the last scene?")
    return questions


def talk(asker: Asker, questions: list[str], console: Console) -> None:
    """Ask each question and print the answer, then each explanation it does not already say."""
    for question in questions:
        answer = asker.ask(question)
        console.print(f"[bold]> {question}[/bold]")
        console.print(f"  {answer.words}", soft_wrap=True)
        for explanation in answer.explanations:
            if explanation.words not in answer.words:
                console.print(f"  [dim]because: {explanation.words}[/dim]", soft_wrap=True)
