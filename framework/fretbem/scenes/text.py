"""Reading a TOML file's text: its size bounded, its encoding found or refused by name.

TOML files are UTF-8. A UTF-8 byte-order mark (as some Windows editors write) is dropped,
and a UTF-16 file with its byte-order mark is decoded (both are unambiguous); any other
encoding (Latin-1, Windows-1252, UTF-16 without a mark) is refused with the byte that is
not UTF-8 and how to save the file. A file larger than :data:`MAX_BYTES` (a runaway
generated history, /dev/zero) is refused before it is read whole.
"""

from __future__ import annotations

import codecs
import sys
from pathlib import Path

from fretbem.errors import InputError

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover
    import tomli as tomllib

__all__ = ["MAX_BYTES", "read_toml", "toml_text"]

#: largest TOML file read (a scene of a million-step history is about 10 MB)
MAX_BYTES = 32 * 2**20


def toml_text(path: str | Path, what: str, error: type[InputError] = InputError) -> str:
    """The text of the file at ``path`` (``what`` names it in messages: "scene file")."""
    path = Path(path)
    try:
        with open(path, "rb") as handle:
            data = handle.read(MAX_BYTES + 1)
    except OSError as err:
        raise error(f"cannot read {what} {path}: {err.strerror or err}") from None
    if len(data) > MAX_BYTES:
        raise error(
            f"{path}: the {what} is larger than {MAX_BYTES // 2**20} MB (a runaway generated "
            "file?); a load history of that length would not fit in memory either: split it "
            "into shorter runs"
        )
    if data.startswith(codecs.BOM_UTF8):
        data = data[len(codecs.BOM_UTF8) :]
    elif data.startswith((codecs.BOM_UTF16_LE, codecs.BOM_UTF16_BE)):
        try:
            return data.decode("utf-16")
        except UnicodeDecodeError as err:
            raise error(f"{path}: the {what} starts with a UTF-16 mark but is not UTF-16 text "
                        f"({err.reason}); save it as UTF-8") from None  # fmt: skip
    if b"\0" in data:
        raise error(
            f"{path}: the {what} holds NUL bytes, so it is not a text file (UTF-16 without a "
            "byte-order mark, or binary data); save it as UTF-8 text"
        )
    try:
        return data.decode("utf-8")
    except UnicodeDecodeError as err:
        byte = data[err.start]
        line = data[: err.start].count(b"\n") + 1
        raise error(
            f"{path}: the {what} is not UTF-8 (byte 0x{byte:02x} on line {line}, e.g. a "
            "Latin-1 or Windows-1252 character such as a degree sign or mu); TOML files are "
            "UTF-8: save it as UTF-8 in your editor"
        ) from None


def read_toml(path: str | Path, what: str, error: type[InputError] = InputError) -> dict:
    """The parsed TOML table of the file at ``path``."""
    text = toml_text(path, what, error)
    try:
        return tomllib.loads(text)
    except tomllib.TOMLDecodeError as err:
        raise error(f"{path}: the {what} is not valid TOML: {err}") from None
