"""Resetters sphinx-gallery calls before every gallery script (``reset_modules``)."""

from __future__ import annotations


def reset_pyvista(gallery_conf, fname) -> None:
    """Restore pyvista's global theme and close its plotters, if a script imported pyvista."""
    import sys

    pyvista = sys.modules.get("pyvista")
    if pyvista is None:
        return
    pyvista.close_all()
    pyvista.global_theme.restore_defaults()
    pyvista.OFF_SCREEN = True
