"""The settings of a memory on a SPARQL server and of recordings on object storage: unset means
the embedded default; bad values name the field."""

import pytest
from pydantic import ValidationError

from api.config import Settings


def test_unset_means_the_embedded_store_and_local_recordings() -> None:
    settings = Settings()
    assert (settings.store_url, settings.streams_url, settings.follow) == (None, None, False)


@pytest.mark.parametrize(
    ("field", "value"),
    [
        ("store_url", "127.0.0.1:7878"),
        ("store_profile", "virtuoso"),
        ("memory", "robot a"),
        ("lease_s", 0),
        ("streams_url", "https://bucket/prefix"),
        ("streams_url", "s3://B/prefix"),
        ("streams_endpoint", "localhost:5000"),
        ("fleet", "robot-b,"),
        ("fleet", "robot b"),
        ("streams_cache_bytes", -1),
    ],
)
def test_a_bad_value_is_refused_naming_the_field(field: str, value: object) -> None:
    with pytest.raises(ValidationError) as caught:
        Settings(**{field: value})  # type: ignore[arg-type]
    assert caught.value.errors()[0]["loc"] == (field,)


def test_good_values_are_kept() -> None:
    settings = Settings(
        store_url="http://127.0.0.1:7878",
        memory="robot-a",
        follow=True,
        streams_url="s3://engram-fleet/robots/a",
        streams_endpoint="http://127.0.0.1:5000",
        fleet="robot-b,robot-c",
        streams_cache_bytes=0,
    )
    assert (settings.memory, settings.streams_url) == ("robot-a", "s3://engram-fleet/robots/a")
    assert (settings.fleet_memories, settings.streams_cache_bytes) == (["robot-b", "robot-c"], 0)
