"""The vendored libraries are exactly the npm files the manifest names, and the pages load
nothing from anywhere else."""

import hashlib
import json
import re
from pathlib import Path

from api.routes.views import WEB_DIR

VENDOR = WEB_DIR / "vendor"
MANIFEST = json.loads((VENDOR / "manifest.json").read_text())


def test_every_vendored_file_matches_its_manifest_entry() -> None:
    entries = {e["file"]: e for e in MANIFEST["files"]}
    on_disk = {p.name for p in VENDOR.iterdir() if p.is_file() and p.name != "manifest.json"}
    assert on_disk == set(entries)
    for name, entry in entries.items():
        assert set(entry) >= {"package", "version", "licence", "sha256", "source"}, name
        assert re.fullmatch(r"\d+\.\d+\.\d+", entry["version"]), name
        digest = hashlib.sha256((VENDOR / name).read_bytes()).hexdigest()
        assert digest == entry["sha256"], f"{name} differs from {entry['source']}"
        assert (VENDOR / entry["licence_file"]).is_file(), name


def _references(path: Path) -> list[str]:
    text = path.read_text()
    return re.findall(r"""(?:src|href)=["']([^"']+)["']|from\s+["']([^"']+)["']""", text)


def test_the_pages_reference_only_files_of_their_own() -> None:
    for page in [*WEB_DIR.glob("*.html"), *WEB_DIR.glob("*.js"), *WEB_DIR.glob("*.css")]:
        for groups in _references(page):
            ref = next(g for g in groups if g)
            assert "//" not in ref, f"{page.name} loads {ref} from another host"
        assert "@import" not in page.read_text() or page.suffix != ".css"
        assert not re.search(r"https?://(?!w3id\.org|www\.w3\.org)", page.read_text()), page.name
