"""The scene file's error (lowest module of the scenes package: the reader and the legacy
translation both raise it)."""

from __future__ import annotations

from fretbem.errors import InputError

__all__ = ["SceneFileError"]


class SceneFileError(InputError):
    """A scene file with an unknown key, a wrong type, a bad value or a non-finite number."""
