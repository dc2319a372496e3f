"""Where ARMOR's file commands may read, write and fetch: :class:`FileAccess`.

ARMOR itself (a ROS node on the robot) reads and writes any path and fetches any URL its user
names. Engram's server faces HTTP clients, so it confines ``LOAD FILE``, ``SAVE`` and
``LOG FILE ON`` to the data directory and the directories of ``armor_file_dirs`` (a relative
path is relative to the data directory), and ``LOAD WEB`` to the URL prefixes of
``armor_url_prefixes`` (none by default: ``LOAD WEB`` is refused). A path or URL holding a
control character (a newline would forge a log line) is refused everywhere.

An engine made without a policy (embedded in a Python program) uses :data:`ANYWHERE`: any path,
any http(s) URL, as ARMOR does.

>>> from pathlib import Path
>>> access = FileAccess.confined(Path("/srv/engram"), url_prefixes=["https://onto.example/"])
>>> access.path("refs/kitchen.owl")
PosixPath('/srv/engram/refs/kitchen.owl')
>>> access.path("/etc/shadow")  # doctest: +ELLIPSIS
Traceback (most recent call last):
...
api.armor.errors.ResourceError: args[0]: '/etc/shadow' is outside the directories ...
>>> access.url("https://onto.example/kitchen.owl")
'https://onto.example/kitchen.owl'
>>> access.url("https://onto.example.evil/x")  # doctest: +ELLIPSIS
Traceback (most recent call last):
...
api.armor.errors.ResourceError: args[0]: 'https://onto.example.evil/x' is not under a URL ...
"""

import re
from collections.abc import Iterable
from dataclasses import dataclass
from pathlib import Path
from urllib.parse import urlsplit

from api.armor.errors import InvalidArgumentsError, ResourceError

__all__ = ["ANYWHERE", "FileAccess"]

_CONTROL = re.compile(r"[\x00-\x1f\x7f]")


@dataclass(frozen=True)
class FileAccess:
    """The directories ARMOR's file commands may use and the URL prefixes LOAD WEB may fetch;
    None for either means no restriction."""

    directories: tuple[Path, ...] | None = None
    url_prefixes: tuple[str, ...] | None = None

    @classmethod
    def confined(
        cls, data_dir: Path, directories: Iterable[Path] = (), url_prefixes: Iterable[str] = ()
    ) -> "FileAccess":
        """The data directory (where relative paths lead) and ``directories``; only the URLs
        under ``url_prefixes``."""
        roots = [data_dir, *directories]
        return cls(
            tuple(Path(root).resolve() for root in roots),
            tuple(prefix for prefix in url_prefixes if prefix),
        )

    def path(self, text: str, field: str = "args[0]") -> Path:
        """The path ``text`` names, if the commands may use it.

        Raises :class:`InvalidArgumentsError` for an empty path or one with a control
        character, :class:`ResourceError` for one outside the directories (symbolic links
        followed)."""
        if not text or _CONTROL.search(text):
            raise InvalidArgumentsError(f"{field}: got {text!r}, expected a file path")
        if self.directories is None:
            return Path(text)
        path = (self.directories[0] / text).resolve()
        if not any(path.is_relative_to(root) for root in self.directories):
            raise ResourceError(
                f"{field}: {text!r} is outside the directories ARMOR's file commands may use "
                "(the data directory and armor_file_dirs)"
            )
        return path

    def url(self, text: str, field: str = "args[0]") -> str:
        """``text`` if LOAD WEB may fetch it (an http or https URL under an allowed prefix).

        Raises :class:`InvalidArgumentsError` for anything but an http(s) URL without control
        characters, :class:`ResourceError` for a URL under no allowed prefix."""
        parts = urlsplit(text)
        if parts.scheme not in ("http", "https") or not parts.netloc or _CONTROL.search(text):
            raise InvalidArgumentsError(
                f"{field}: got {text!r}, expected an http:// or https:// URL"
            )
        if self.url_prefixes is None or any(_under(text, p) for p in self.url_prefixes):
            return text
        raise ResourceError(
            f"{field}: {text!r} is not under a URL prefix LOAD WEB may fetch (armor_url_prefixes)"
        )


def _under(url: str, prefix: str) -> bool:
    """Whether ``url`` is ``prefix`` or below it: the prefix ends at a path boundary, so that
    ``https://a.example`` does not admit ``https://a.example.evil``."""
    if not url.startswith(prefix):
        return False
    return prefix.endswith("/") or len(url) == len(prefix) or url[len(prefix)] in "/?#"


ANYWHERE = FileAccess()
"""No restriction: any path, any http(s) URL."""
