"""The ``fretbem-cli`` directive: the command's ``--help`` texts, taken from its parser.

The reference page of the command line is generated from :func:`fretbem.app.cli.parser` at
build time, so an option added to the command appears in the docs without editing them.
"""

from __future__ import annotations

import argparse

from docutils import nodes
from sphinx.util.docutils import SphinxDirective


def _help(parser: argparse.ArgumentParser) -> str:
    """``--help`` text at a fixed width, so the page does not depend on the terminal."""
    parser.formatter_class = lambda prog: argparse.HelpFormatter(prog, width=88)
    return parser.format_help()


class FretbemCliDirective(SphinxDirective):
    """Render ``fretbem --help`` and ``fretbem COMMAND --help`` for every sub-command."""

    has_content = False

    def run(self) -> list[nodes.Node]:
        from fretbem.app import cli

        main = cli.parser()
        out: list[nodes.Node] = [nodes.literal_block(text=_help(main), language="text")]
        commands = next(a for a in main._actions if isinstance(a, argparse._SubParsersAction))
        for name, sub in commands.choices.items():
            section = nodes.section(ids=[nodes.make_id(f"fretbem-{name}")])
            section += nodes.title(text=f"fretbem {name}")
            section += nodes.literal_block(text=_help(sub), language="text")
            out.append(section)
        return out


def setup(app):
    app.add_directive("fretbem-cli", FretbemCliDirective)
    return {"parallel_read_safe": True, "parallel_write_safe": True}
