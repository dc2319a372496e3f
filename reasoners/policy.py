"""The memory policy: every threshold, weight and time constant, read from the store.

>>> from kg import Store, ensure_ontology
>>> store = Store()
>>> _ = ensure_ontology(store)
>>> load_policy(store).learn_threshold
0.8
"""

from dataclasses import dataclass, fields

from pyoxigraph import Literal, NamedNode

from kg.store import Store
from ontologies.vocab import DEFAULT_POLICY, engram
from reasoners.errors import PolicyError

__all__ = ["Policy", "load_policy"]


@dataclass(frozen=True)
class Policy:
    """The values of one ``engram:MemoryPolicy`` individual (field = property local name)."""

    alignedThresholdX: float
    alignedThresholdY: float
    alignedThresholdZ: float
    parallelThreshold: float
    perpendicularThreshold: float
    coaxialThreshold: float
    learnThreshold: float
    complexityWeight: float
    childrenWeight: float
    storeWeight: float
    retrieveWeight: float
    episodicComplexityWeight: float
    episodicChildrenWeight: float
    episodicStoreWeight: float
    episodicRetrieveWeight: float
    decayWeight: float
    decayTimeConstantSeconds: float
    highLevelThreshold: float
    weakLevelThreshold: float
    weakPassesToForget: int
    forgetGracePeriodSeconds: float
    sleepEveryUpdates: int
    sleepIntervalSeconds: float

    @property
    def learn_threshold(self) -> float:
        return self.learnThreshold


def load_policy(store: Store, policy: NamedNode = DEFAULT_POLICY) -> Policy:
    """Read ``policy`` from the store.

    Raises :class:`PolicyError` naming the property when a value is missing or not a number.
    """
    values: dict[str, Literal] = {}
    for row in store.select("memory_policy", policy=policy):
        prop, value = row["property"], row["value"]
        if isinstance(value, Literal) and prop.value.startswith(engram("").value):
            values[prop.value.removeprefix(engram("").value)] = value
    kwargs: dict[str, float | int] = {}
    for spec in fields(Policy):
        literal = values.get(spec.name)
        if literal is None:
            raise PolicyError(
                f"memory policy {policy.value}: engram:{spec.name} is missing; "
                "expected one value (is the Engram ontology loaded?)"
            )
        try:
            number = float(literal.value)
        except ValueError:
            raise PolicyError(
                f"memory policy {policy.value}: engram:{spec.name}: got {literal.value!r}, "
                "expected a number"
            ) from None
        if spec.type is int or spec.type == "int":
            if number != int(number) or number < 1:
                raise PolicyError(
                    f"memory policy {policy.value}: engram:{spec.name}: got {literal.value!r}, "
                    "expected a positive integer"
                )
            kwargs[spec.name] = int(number)
        else:
            if number < 0:
                raise PolicyError(
                    f"memory policy {policy.value}: engram:{spec.name}: got {literal.value!r}, "
                    "expected a non-negative number"
                )
            kwargs[spec.name] = number
    return Policy(**kwargs)  # type: ignore[arg-type]
