"""Recordings on S3-compatible object storage: write-once upload, ranged fetch, delete.

Pure files and HTTP (boto3), no RDF. An episode's bag directory (its MCAP file and
``metadata.yaml``) is uploaded once it has ended, under ``s3://bucket/prefix/<episode>/<file>``;
each object is written once (``If-None-Match: *``: a second upload of the same key is refused,
never an overwrite) and described by its URI, size and SHA-256. Reading fetches the objects
back into a local directory with parallel ranged GETs, checks size and digest, and only then
moves the file into place, so a reader never sees a partial file.

>>> parse_url("s3://engram-fleet/robots/a")
('engram-fleet', 'robots/a')
"""

import hashlib
import logging
import os
import re
import shutil
import tempfile
import uuid
from collections.abc import Iterable
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import boto3
import botocore.config
import botocore.exceptions

from episodes.streams.errors import StreamError

__all__ = ["ObjectStorageError", "ObjectStore", "StoredObject", "parse_url"]

log = logging.getLogger(__name__)

_URL = re.compile(r"s3://([a-z0-9][a-z0-9.-]{1,61}[a-z0-9])(?:/(.*))?")
PART_BYTES = 64 * 1024 * 1024
"""Multipart part size, and the size of one ranged read."""


class ObjectStorageError(StreamError):
    """The object storage refused or failed a request (the message names the object)."""


@dataclass(frozen=True)
class StoredObject:
    """One uploaded file: where it is, how large, and its SHA-256 (hex)."""

    uri: str
    size: int
    sha256: str

    @property
    def name(self) -> str:
        return self.uri.rsplit("/", 1)[-1]


def parse_url(url: str) -> tuple[str, str]:
    """``s3://bucket/prefix`` as (bucket, prefix without slashes at its ends).

    Raises ``ValueError`` naming the value when it is not such a URL.
    """
    match = _URL.fullmatch(url) if isinstance(url, str) else None
    if match is None:
        raise ValueError(f"streams url: got {url!r}, expected s3://bucket/prefix")
    return match.group(1), (match.group(2) or "").strip("/")


def _sha256(path: Path) -> str:
    digest = hashlib.sha256()
    with path.open("rb") as file:
        while chunk := file.read(8 * 1024 * 1024):
            digest.update(chunk)
    return digest.hexdigest()


class ObjectStore:
    """A bucket and prefix on an S3-compatible service (``endpoint_url``; None means AWS).

    ``workers`` parts or ranges move at once.
    """

    def __init__(
        self,
        url: str,
        *,
        endpoint_url: str | None = None,
        workers: int = 8,
        client: Any = None,
    ) -> None:
        self.bucket, self.prefix = parse_url(url)
        self.workers = workers
        self._client = client or boto3.client(
            "s3",
            endpoint_url=endpoint_url,
            config=botocore.config.Config(
                max_pool_connections=workers * 2,
                retries={"max_attempts": 3, "mode": "standard"},
                connect_timeout=5,
                read_timeout=60,
            ),
        )

    def uri(self, key: str) -> str:
        return f"s3://{self.bucket}/{key}"

    def _key(self, uri: str) -> str:
        bucket, key = parse_url(uri)
        if bucket != self.bucket or not key.startswith(self.prefix):
            raise ValueError(
                f"uri: got {uri!r}, expected an object under s3://{self.bucket}/{self.prefix}"
            )
        return key

    # Writing -------------------------------------------------------------------------------------

    def upload_directory(self, directory: Path, name: str) -> list[StoredObject]:
        """Upload every file of ``directory`` under ``<prefix>/<name>/``, each write-once."""
        files = sorted(p for p in directory.iterdir() if p.is_file())
        return [self.upload(path, f"{name}/{path.name}") for path in files]

    def upload(self, path: Path, name: str) -> StoredObject:
        """Upload one file as ``<prefix>/<name>``, once.

        Raises :class:`ObjectStorageError` if the object already exists with other content (an
        identical one is accepted: the upload was repeated after a crash) or the service fails.
        """
        key = f"{self.prefix}/{name}" if self.prefix else name
        size, digest = path.stat().st_size, _sha256(path)
        stored = StoredObject(self.uri(key), size, digest)
        existing = self._head(key)
        if existing is not None:
            if existing.get("Metadata", {}).get("sha256") == digest:
                return stored
            raise ObjectStorageError(
                f"{stored.uri} already exists with other content; not overwritten"
            )
        try:
            if size <= PART_BYTES:
                self._client.put_object(
                    Bucket=self.bucket,
                    Key=key,
                    Body=path.read_bytes(),
                    Metadata={"sha256": digest},
                    IfNoneMatch="*",
                )
            else:
                self._multipart(path, key, size, digest)
        except botocore.exceptions.ClientError as error:
            code = error.response.get("Error", {}).get("Code", "")
            if code == "PreconditionFailed":
                raise ObjectStorageError(f"{stored.uri} already exists; not overwritten") from None
            raise ObjectStorageError(f"upload of {stored.uri} failed: {error}") from error
        except botocore.exceptions.BotoCoreError as error:
            raise ObjectStorageError(f"upload of {stored.uri} failed: {error}") from error
        log.info("uploaded %s (%d bytes)", stored.uri, size)
        return stored

    def _multipart(self, path: Path, key: str, size: int, digest: str) -> None:
        upload = self._client.create_multipart_upload(
            Bucket=self.bucket, Key=key, Metadata={"sha256": digest}
        )["UploadId"]

        def part(number: int) -> dict[str, Any]:
            with path.open("rb") as file:
                file.seek((number - 1) * PART_BYTES)
                body = file.read(PART_BYTES)
            answer = self._client.upload_part(
                Bucket=self.bucket, Key=key, UploadId=upload, PartNumber=number, Body=body
            )
            return {"ETag": answer["ETag"], "PartNumber": number}

        count = (size + PART_BYTES - 1) // PART_BYTES
        try:
            with ThreadPoolExecutor(self.workers) as pool:
                parts = list(pool.map(part, range(1, count + 1)))
            self._client.complete_multipart_upload(
                Bucket=self.bucket,
                Key=key,
                UploadId=upload,
                MultipartUpload={"Parts": parts},
                IfNoneMatch="*",
            )
        except BaseException:
            self._client.abort_multipart_upload(Bucket=self.bucket, Key=key, UploadId=upload)
            raise

    def _head(self, key: str) -> dict[str, Any] | None:
        try:
            answer: dict[str, Any] = self._client.head_object(Bucket=self.bucket, Key=key)
            return answer
        except botocore.exceptions.ClientError as error:
            if error.response.get("Error", {}).get("Code") in ("404", "NoSuchKey", "NotFound"):
                return None
            raise ObjectStorageError(f"cannot read s3://{self.bucket}/{key}: {error}") from error

    # Reading -------------------------------------------------------------------------------------

    def read_range(self, uri: str, start: int, length: int) -> bytes:
        """``length`` bytes of an object from offset ``start`` (one ranged GET)."""
        key = self._key(uri)
        try:
            answer = self._client.get_object(
                Bucket=self.bucket, Key=key, Range=f"bytes={start}-{start + length - 1}"
            )
            data: bytes = answer["Body"].read()
            return data
        except (botocore.exceptions.ClientError, botocore.exceptions.BotoCoreError) as error:
            raise ObjectStorageError(f"cannot read {uri}: {error}") from error

    def fetch(self, stored: StoredObject, target: Path) -> Path:
        """Download ``stored`` to the file ``target`` by parallel ranged reads; check its size
        and SHA-256 before it appears at ``target``. Returns ``target``.

        Raises :class:`ObjectStorageError` if the object is missing, differs from its
        description (nothing is left at ``target``), or the service fails.
        """
        target.parent.mkdir(parents=True, exist_ok=True)
        fd, temporary = tempfile.mkstemp(dir=target.parent, prefix=f".{target.name}.")
        os.close(fd)
        partial = Path(temporary)
        try:
            with partial.open("r+b") as file:
                file.truncate(stored.size)

            def one(start: int) -> None:
                data = self.read_range(stored.uri, start, min(PART_BYTES, stored.size - start))
                with partial.open("r+b") as file:
                    file.seek(start)
                    file.write(data)

            with ThreadPoolExecutor(self.workers) as pool:
                list(pool.map(one, range(0, stored.size, PART_BYTES)))
            if partial.stat().st_size != stored.size or _sha256(partial) != stored.sha256:
                raise ObjectStorageError(
                    f"{stored.uri}: the fetched bytes do not match the recorded size and sha256"
                )
            partial.replace(target)
        finally:
            partial.unlink(missing_ok=True)
        return target

    def fetch_all(self, objects: Iterable[StoredObject], directory: Path) -> Path:
        """Fetch objects into a new ``directory`` (all of them appear together, or none)."""
        staging = directory.with_name(f".fetching-{directory.name}-{uuid.uuid4().hex[:8]}")
        try:
            for stored in objects:
                self.fetch(stored, staging / stored.name)
            staging.rename(directory)
        finally:
            shutil.rmtree(staging, ignore_errors=True)
        return directory

    # Deleting ------------------------------------------------------------------------------------

    def delete(self, uris: Iterable[str]) -> None:
        """Delete objects (missing ones are not an error)."""
        keys = [{"Key": self._key(uri)} for uri in uris]
        for start in range(0, len(keys), 1000):
            try:
                self._client.delete_objects(
                    Bucket=self.bucket, Delete={"Objects": keys[start : start + 1000]}
                )
            except (botocore.exceptions.ClientError, botocore.exceptions.BotoCoreError) as error:
                raise ObjectStorageError(
                    f"cannot delete objects in {self.bucket}: {error}"
                ) from error
