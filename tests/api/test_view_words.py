"""The views say a class's definition in the words of its stored label."""

import pytest

from api.views.words import words
from ontologies.vocab import PLANE, engram
from reasoners.labels import RELATION_WORDS, label
from reasoners.signature import Signature


@pytest.mark.parametrize("relation", sorted(RELATION_WORDS))
def test_a_relation_reads_as_in_the_stored_label(relation: str) -> None:
    scene_property = "cone" + relation[0].upper() + relation[1:]
    stored = label(Signature({(engram(scene_property), PLANE): 1}))
    assert words([(scene_property, "Plane", 1)]) == f"a {stored}"
