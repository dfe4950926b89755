"""Sphinx extension: read quatnav's docstrings the way they are written.

The docstrings are numpydoc, written to be read in ``help()`` first. Three habits of plain text
would be reST errors; this hook (run before napoleon) turns them into what they mean:

* ``|x|`` outside inline literals is an absolute value or a norm, never a substitution: the
  bars are escaped.
* A heading underlined with dashes that napoleon does not know (``Integration scheme (...)``)
  becomes a rubric, and a known section with a note in brackets
  (``Parameters (keyword, SI units; ...)``) becomes the plain section preceded by the note.
* A class as a default value (``dtype=<class 'numpy.float64'>``) is shown by its name.
* A re-exported constant (``quatnav.FLAGS``) gets the ``#:`` comment of the module that defines
  it instead of its type's docstring, and a dict of bits gets the list of its keys and bits.
"""
from __future__ import annotations

import re
import sys

_SECTIONS = ("Parameters", "Other Parameters", "Returns", "Yields", "Receives", "Raises",
             "Warns", "Attributes", "Methods", "Notes", "References", "Examples", "See Also",
             "Warning", "Warnings", "Keyword Arguments", "Args", "Arguments")
_DASHES = re.compile(r"^\s*-{3,}\s*$")
_NOTE_SECTION = re.compile(r"^(%s)\s*\((.+)\)\s*:?$" % "|".join(_SECTIONS))
_LITERAL = re.compile(r"(``.+?``|`[^`]*`)", re.S)  # inline literals and roles, also across lines
_ABS = re.compile(r"(?<![\\|])\|(?=\S)([^|`\n]*?\S)\|(?!\|)")


def _escape_bars(lines: list[str]) -> list[str]:
    parts = _LITERAL.split("\n".join(lines))
    for i in range(0, len(parts), 2):  # even indices: outside literals and roles
        rows = parts[i].split("\n")
        for j, row in enumerate(rows):
            starts_line = j > 0 or i == 0 or parts[i - 1].endswith("\n")
            if starts_line and row.lstrip().startswith(("|", "+")):
                continue  # a line block or a table row: leave it
            rows[j] = _ABS.sub(r"\\|\1\\|", row)
        parts[i] = "\n".join(rows)
    return "".join(parts).split("\n")


def _headings(lines: list[str]) -> list[str]:
    out, i = [], 0
    while i < len(lines):
        line = lines[i]
        nxt = lines[i + 1] if i + 1 < len(lines) else ""
        if line.strip() and not _DASHES.match(line) and _DASHES.match(nxt):
            indent = line[: len(line) - len(line.lstrip())]
            title = line.strip()
            m = _NOTE_SECTION.match(title)
            if m:
                out += [indent + f"{m.group(1)}: {m.group(2)}.", "", indent + m.group(1),
                        indent + "-" * len(m.group(1))]
            elif title.rstrip(":") in _SECTIONS:
                out += [line, nxt]
            else:
                out += [indent + ".. rubric:: " + title, ""]
            i += 2
            continue
        out.append(line)
        i += 1
    return out


def _is_field(lines: list[str], i: int) -> bool:
    """Line i starts a numpydoc field: ``name : type`` or a name followed by an indented line."""
    line = lines[i]
    nxt = lines[i + 1] if i + 1 < len(lines) else ""
    return " : " in line or line.rstrip().endswith(" :") or (nxt[:1].isspace() and nxt.strip() != "")


def _paragraphs_in_parameters(lines: list[str]) -> list[str]:
    """End a Parameters section at a plain paragraph (napoleon would read it as a parameter)
    and go on with "Parameters (continued)" at the next field after it."""
    out, mode = [], None  # mode: None, "params" (in the section), "text" (paragraph inside it)
    for i, line in enumerate(lines):
        nxt = lines[i + 1] if i + 1 < len(lines) else ""
        if line.strip() and _DASHES.match(nxt):
            mode = "params" if line.strip() in ("Parameters", "Other Parameters", "Parameters (continued)") else None
        elif mode and line.strip() and not line[:1].isspace() and (i == 0 or not lines[i - 1].strip()) \
                and not _DASHES.match(line):
            if mode == "params" and not _is_field(lines, i):
                out.append("")  # two blank lines: napoleon closes the section
                mode = "text"
            elif mode == "text" and _is_field(lines, i):
                out += ["Parameters (continued)", "-" * len("Parameters (continued)")]
                mode = "params"
        out.append(line)
    return out


def _defining_comment(name: str, obj) -> list[str] | None:
    """The ``#:`` comment of ``name``'s last part in the quatnav module that defines it."""
    from sphinx.pycode import ModuleAnalyzer
    attr = name.rsplit(".", 1)[-1]
    # Only modules already imported: importing others could run code (quatnav.__main__).
    for modname, mod in sorted(sys.modules.items()):
        if not modname.startswith("quatnav.") or getattr(mod, attr, None) is not obj:
            continue
        try:
            docs = ModuleAnalyzer.for_module(modname).find_attr_docs()
        except Exception:  # noqa: BLE001 - a compiled module has no source to analyze
            continue
        if ("", attr) in docs:
            return list(docs[("", attr)])
    return None


def process_docstring(app, what, name, obj, options, lines):
    if what in ("data", "attribute") and name.startswith("quatnav.") and not isinstance(obj, (str, int, float)):
        type_doc = " ".join((type(obj).__doc__ or "").split())
        if lines and " ".join(" ".join(lines).split()) == type_doc:
            lines[:] = _defining_comment(name, obj) or []
        if isinstance(obj, dict) and obj and all(isinstance(v, int) for v in obj.values()):
            lines += ["", *(f"* ``{k}``: bit {v.bit_length() - 1} (``{v:#x}``)" for k, v in obj.items())]
    lines[:] = _escape_bars(_paragraphs_in_parameters(_headings(lines)))


_CLASS_REPR = re.compile(r"<class '([\w.]+)'>")


def process_signature(app, what, name, obj, options, signature, return_annotation):
    """A class as a default value reads as its name: ``dtype=numpy.float64``."""
    if signature:
        signature = _CLASS_REPR.sub(r"\1", signature)
    return signature, return_annotation


def setup(app):
    app.connect("autodoc-process-docstring", process_docstring, priority=100)  # before napoleon
    app.connect("autodoc-process-signature", process_signature)
    custom = list(app.config.napoleon_custom_sections or [])
    if ("Parameters (continued)", "params_style") not in custom:
        app.config.napoleon_custom_sections = [*custom, ("Parameters (continued)", "params_style")]
    return {"version": "1", "parallel_read_safe": True, "parallel_write_safe": True}
