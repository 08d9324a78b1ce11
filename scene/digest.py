"""SHA-256 digests of a generated model's files and of its manifest (pure Python, no sympy).

manifest.json lists the sha256 of every other file of the folder (`files`) and the sha256 of its
own canonical JSON without the `manifest_sha256` key (`manifest_sha256`), so an edited, truncated
or swapped file, or an edited manifest, is detected before anything is used
(derive/build.py writes both; runtime/model/manifest.py checks them).
"""
from __future__ import annotations

import hashlib
import json
from pathlib import Path

SELF_KEY = "manifest_sha256"


def sha256_hex(data: bytes) -> str:
    return hashlib.sha256(data).hexdigest()


def file_digests(files: dict[str, bytes]) -> dict[str, str]:
    """name -> sha256 of its bytes, in name order."""
    return {name: sha256_hex(data) for name, data in sorted(files.items())}


def manifest_digest(manifest: dict) -> str:
    """The sha256 of the manifest's canonical JSON without its own digest."""
    body = {k: v for k, v in manifest.items() if k != SELF_KEY}
    return sha256_hex(json.dumps(body, sort_keys=True, separators=(",", ":")).encode())


def first_changed_file(folder: Path, digests: dict[str, str]) -> tuple[str, str] | None:
    """(name, "missing" | "changed") of the first file of `folder` that is not what `digests` says;
    None when every file is intact."""
    for name, expected in sorted(digests.items()):
        try:
            data = (Path(folder) / name).read_bytes()
        except (FileNotFoundError, NotADirectoryError, IsADirectoryError):
            return name, "missing"
        if sha256_hex(data) != expected:
            return name, "changed"
    return None
