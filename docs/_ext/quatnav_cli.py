"""Sphinx extension: the command line's reference, made from its parsers.

``quatnav-cli`` renders every command of :func:`quatnav.cli.build_parser` (``quatnav ins run``,
``quatnav ahrs run``, ...) as a section with its ``-h`` text, so the page lists what a user
types, and can never disagree with the command::

    ```{quatnav-cli}
    ```
"""
from __future__ import annotations

import argparse
import os

from docutils import nodes
from docutils.parsers.rst import Directive


def commands(parser, path=()):
    """(words after 'quatnav', parser) of every command that runs something, depth first, in
    the order 'quatnav -h' lists them; the top level first."""
    out = [(path, parser)]
    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            for name, sub in action.choices.items():
                out += commands(sub, path + (name,))
    return out


def help_text(parser) -> str:
    """``PROG -h`` at 100 columns (the width the commands' texts are written for)."""
    saved = os.environ.get("COLUMNS")
    os.environ["COLUMNS"] = "100"
    try:
        return parser.format_help()
    finally:
        if saved is None:
            os.environ.pop("COLUMNS", None)
        else:
            os.environ["COLUMNS"] = saved


class QuatnavCli(Directive):
    """A section per command with its help, made from the argparse tree."""

    has_content = True

    def run(self):
        from quatnav.cli import build_parser
        out = []
        for words, parser in commands(build_parser()):
            title = " ".join(("quatnav",) + words)
            section = nodes.section(ids=[nodes.make_id(title)])
            section += nodes.title(text=title)
            block = nodes.literal_block(text=help_text(parser).rstrip())
            block["language"] = "text"
            section += block
            out.append(section)
        return out


def setup(app):
    app.add_directive("quatnav-cli", QuatnavCli)
    return {"version": "1", "parallel_read_safe": True, "parallel_write_safe": True}
