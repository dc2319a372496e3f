"""armor_msgs as Engram generates them: ARMOR's definitions, hence ARMOR's md5sums."""

import hashlib

import pytest

from api.ros.messages import DEFINITIONS, armor_msgs, md5sums_of_definitions
from api.ros.system import load_ros

load_ros()

# git's blob ids of the files of EmaroLab/armor_msgs at 0acfcd0 (its newest commit): Engram's
# definitions declare exactly ARMOR's interface, byte for byte.
UPSTREAM_BLOBS = {
    "msg/ArmorDirectiveReq.msg": "1251ff74e1fec41691754d689815344dfe2038c2",
    "msg/ArmorDirectiveRes.msg": "7a9f954fe9c3e8cb932e859e7faafca20ba76c60",
    "msg/QueryItem.msg": "084576c7781a2b7265b430ae193b9ead47d16f2b",
    "srv/ArmorDirective.srv": "e4cf578c53e560bf4d1d669e7c40ad54f94642f8",
    "srv/ArmorDirectiveList.srv": "de681e502d46ad996e5b5f61d101a47e8939a281",
}

# What ROS compares when an ARMOR client connects (genmsg's md5 of those definitions).
ARMOR_MD5SUMS = {
    "armor_msgs/ArmorDirective": "39cbf11e18dc47e2c7b5fda84e5d8c39",
    "armor_msgs/ArmorDirectiveList": "c8f7a3567fd279dae5ca45853049f5a7",
    "armor_msgs/ArmorDirectiveReq": "385184fa98c36b7f00729ae2078dfc92",
}


def _blob_id(data: bytes) -> str:
    return hashlib.sha1(b"blob %d\0" % len(data) + data).hexdigest()


@pytest.mark.parametrize(("path", "blob"), sorted(UPSTREAM_BLOBS.items()))
def test_the_definitions_are_armors_interface_byte_for_byte(path: str, blob: str) -> None:
    assert _blob_id((DEFINITIONS / path).read_bytes()) == blob


def test_generated_classes_carry_the_md5sums_of_armors_definitions() -> None:
    computed = md5sums_of_definitions()
    types = armor_msgs()
    for module in (types.msg, types.srv):
        for name, md5 in computed.items():
            cls = getattr(module, name.split("/")[1], None)
            if cls is not None:
                assert cls._md5sum == md5, name
                assert cls._type == name
    for name, md5 in ARMOR_MD5SUMS.items():
        assert computed[name] == md5
