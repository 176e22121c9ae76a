"""The JSON files the tool writes beside contracts (baselines, the type lock) name their format
and version; reading one checks both before anything else is looked at."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

from ..errors import InputError, UnreadableFile
from . import untrusted


def read(path: str | Path, *, file_format: str, version: int, what: str) -> dict[str, Any]:
    """The JSON object in ``path`` whose ``"format"`` is ``file_format`` and ``"version"`` is
    ``version`` (raises :class:`UnreadableFile`; ``what``: "a baseline", "a type lock")."""
    try:  # bounded, and a FIFO is refused before anything opens it (issue 50, N22: it blocked forever)
        document = json.loads(untrusted.read_text(Path(path)))
    except FileNotFoundError:
        raise UnreadableFile("the file does not exist") from None
    except InputError as exc:
        raise UnreadableFile(f"cannot be read: {exc}") from None
    except (OSError, RecursionError, json.JSONDecodeError) as exc:
        raise UnreadableFile(f"not a readable JSON file ({exc})") from None
    if not isinstance(document, dict) or document.get("format") != file_format:
        raise UnreadableFile(f"not {what} (it needs \"format\": \"{file_format}\")")
    if document.get("version") != version:
        raise UnreadableFile(f"version {document.get('version')!r} is not supported (this tool reads {version})")
    return document
