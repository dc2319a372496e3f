"""The experienced scenes (episodic items) the memory holds, by IRI and by class."""

from collections import Counter
from collections.abc import Iterable
from dataclasses import dataclass, field

from pyoxigraph import NamedNode

from reasoners.records import ItemRecord
from reasoners.score_table import move_count

__all__ = ["ItemTable"]


@dataclass
class ItemTable:
    """The items by IRI (``records``), each class's items (``items_of``: every live class has
    a set, kept by the class graph) and how many items have each complexity."""

    records: dict[NamedNode, ItemRecord] = field(default_factory=dict)
    items_of: dict[NamedNode, set[NamedNode]] = field(default_factory=dict)
    complexities: Counter[int] = field(default_factory=Counter)

    @property
    def max_complexity(self) -> int:
        return max(self.complexities, default=0)

    def add(self, record: ItemRecord) -> None:
        self.records[record.iri] = record
        self.items_of.setdefault(record.cls, set()).add(record.iri)
        self.complexities[record.complexity] += 1

    def add_all(self, records: Iterable[ItemRecord]) -> None:
        """:meth:`add` of many items, the counter filled at once."""
        records = list(records)
        self.records.update((r.iri, r) for r in records)
        items_of = self.items_of
        for record in records:
            items_of.setdefault(record.cls, set()).add(record.iri)
        self.complexities.update(r.complexity for r in records)

    def remove(self, item: NamedNode) -> ItemRecord:
        """Drop an item (KeyError if absent) and return its record."""
        record = self.records.pop(item)
        self.items_of.get(record.cls, set()).discard(item)
        move_count(self.complexities, record.complexity, None)
        return record
