"""``client.utils``: armor_py_api's ``ArmorUtilsClient``."""

from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from api.client._client import ArmorClient

__all__ = ["ArmorUtilsClient"]


class ArmorUtilsClient:
    """Loading, mounting, buffers, saving and logging."""

    def __init__(self, client: "ArmorClient") -> None:
        self._client = client

    def load_ref_from_file(
        self,
        owl_file_path: str,
        iri: str,
        buffered_manipulation: bool = False,
        reasoner: str = "PELLET",
        buffered_reasoner: bool = False,
        mounted: bool = False,
    ) -> None:
        args = [owl_file_path, iri, str(buffered_manipulation), reasoner, str(buffered_reasoner)]
        self._client.checked("LOAD", "FILE", "MOUNTED" if mounted else "", args)

    def load_ref_from_web(
        self,
        url: str,
        iri: str,
        buffered_manipulation: bool = False,
        reasoner: str = "PELLET",
        buffered_reasoner: bool = False,
        mounted: bool = False,
    ) -> None:
        args = [url, iri, str(buffered_manipulation), reasoner, str(buffered_reasoner)]
        self._client.checked("LOAD", "WEB", "MOUNTED" if mounted else "", args)

    def mount_on_ref(self) -> None:
        self._client.checked("MOUNT", "", "", [])

    def unmount_from_ref(self) -> None:
        self._client.checked("UNMOUNT", "", "", [])

    def drop_ref(self) -> None:
        self._client.checked("DROP", "", "", [])

    def apply_buffered_changes(self) -> bool:
        return self._client.checked("APPLY", "", "", []).is_consistent

    def sync_buffered_reasoner(self) -> bool:
        return self._client.checked("REASON", "", "", []).is_consistent

    def save(self, filepath: str = "", inference: bool = False) -> None:
        if inference:
            self._client.checked("SAVE", "INFERENCE", "", [filepath])
        else:
            self._client.checked("SAVE", "", "", [filepath])

    def save_ref_with_inferences(self, filepath: str = "") -> None:
        self.save(filepath, inference=True)

    def set_log_to_terminal(self, switch_on: bool) -> None:
        self._client.checked("LOG", "SCREEN", "ON" if switch_on else "OFF", [])

    def set_log_to_file(self, switch_on: bool, filepath: str = "") -> None:
        """Fixed: armor_py_api's OFF branch raised a TypeError."""
        if switch_on:
            self._client.checked("LOG", "FILE", "ON", [filepath])
        else:
            self._client.checked("LOG", "FILE", "OFF", [])

    def get_all_refs(self) -> list[str]:
        return list(self._client.checked("GET", "ALL", "REFS", []).queried_objects)

    def get_ref_client(self, reference_name: str | None = None) -> str:
        name = reference_name or self._client.reference_name
        return self._client.checked("GET", "REF", "CLIENT", [name]).queried_objects[0]
