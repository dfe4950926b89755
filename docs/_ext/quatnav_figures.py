"""Sphinx extension: the figures of the demo and the experiments, made at build time.

Each figure is made by running one of quatnav's own commands (``python -m quatnav ...``) with
the interpreter and the ``quatnav`` that Sphinx uses, into a folder beside the HTML output
(``<outdir>/../figures`` unless ``quatnav_figures_dir`` is set), so no image is ever written to
the sources. A figure is made again when its command changed or the package's files are newer
than it. In a page::

    ```{quatnav-figure} demo
    Caption text.
    ```

The caption ends with the command that made the figure.

A command that fails is reported as a warning naming the command, its exit status and the end
of its error output (``sphinx-build -W`` then fails), and the page says the figure is missing.
"""
from __future__ import annotations

import os
import subprocess
import sys
import time
from pathlib import Path

from docutils import nodes
from docutils.statemachine import StringList
from docutils.parsers.rst.directives.images import Figure
from sphinx.util import logging

logger = logging.getLogger(__name__)

#: name -> arguments of ``python -m quatnav`` ({png} and {json} are replaced by paths).
FIGURES: dict[str, list[str]] = {
    "demo": ["demo", "--plot", "{png}"],
    "marg-turn": ["experiment", "marg-turn", "--json", "{json}", "--plot", "{png}"],
    "nav13": ["experiment", "nav13", "--runs", "10", "--cost-repeats", "3", "--json", "{json}",
              "--plot", "{png}"],
    "paper004_walk": ["simulate", "paper004_walk", "--seed", "0", "--plot", "{png}"],
    "paper002_straight_then_circle": ["simulate", "paper002_straight_then_circle", "--seed", "0",
                                      "--plot", "{png}"],
}

TIMEOUT_S = 600


def command_line(name: str) -> str:
    """The figure's command as a user would type it (``quatnav ...``, file names only)."""
    args = [a.format(png=f"{name}.png", json=f"{name}.json") for a in FIGURES[name]]
    return "quatnav " + " ".join(args)


def _package() -> tuple[Path, float]:
    """The documented quatnav's folder and the time of its newest file."""
    import quatnav
    root = Path(quatnav.__file__).resolve().parent
    return root, max((p.stat().st_mtime for p in root.rglob("*") if p.suffix in (".py", ".so", ".pyd")),
                     default=0.0)


def _child_env() -> dict:
    env = dict(os.environ)
    env["MPLBACKEND"] = "Agg"
    if env.get("PYTHONPATH"):  # relative entries (PYTHONPATH=python) keep working in any cwd
        env["PYTHONPATH"] = os.pathsep.join(str(Path(p).resolve()) for p in env["PYTHONPATH"].split(os.pathsep) if p)
    return env


def _make(name: str, outdir: Path, package: Path, newest_source: float) -> tuple[Path, str | None]:
    png, js, stamp = outdir / f"{name}.png", outdir / f"{name}.json", outdir / f"{name}.cmd"
    args = [a.format(png=png, json=js) for a in FIGURES[name]]
    cmd = [sys.executable, "-m", "quatnav", *args]
    key = f"{package}\n{' '.join(cmd)}"  # the same command with the same package
    if (png.exists() and stamp.exists() and stamp.read_text() == key
            and png.stat().st_mtime >= newest_source):
        logger.info(f"figure {name}: up to date ({png})")
        return png, None
    png.unlink(missing_ok=True)
    stamp.unlink(missing_ok=True)
    t0 = time.perf_counter()
    try:
        r = subprocess.run(cmd, env=_child_env(), capture_output=True, text=True, timeout=TIMEOUT_S)
    except subprocess.TimeoutExpired:
        return png, f"`{command_line(name)}` did not finish within {TIMEOUT_S} s"
    if r.returncode != 0 or not png.exists():
        tail = "\n    ".join((r.stderr or r.stdout).strip().splitlines()[-6:])
        why = f"exited with status {r.returncode}" if r.returncode else "wrote no figure"
        return png, f"`{command_line(name)}` {why}:\n    {tail}"
    stamp.write_text(key)
    logger.info(f"figure {name}: {command_line(name)} ({time.perf_counter() - t0:.1f} s)")
    return png, None


def _generate(app) -> None:
    outdir = Path(app.config.quatnav_figures_dir or Path(app.outdir).parent / "figures").resolve()
    outdir.mkdir(parents=True, exist_ok=True)
    package, newest = _package()
    app.quatnav_figures = {}
    for name in FIGURES:
        png, err = _make(name, outdir, package, newest)
        app.quatnav_figures[name] = (png, err)
        if err:
            logger.warning(f"figure {name!r} could not be made: {err}")


class QuatnavFigure(Figure):
    """``quatnav-figure NAME``: a figure of :data:`FIGURES`; the content is its caption."""

    def run(self):
        env = self.state.document.settings.env
        name = self.arguments[0]
        if name not in FIGURES:
            raise self.error(f"unknown quatnav figure {name!r}; known: {', '.join(FIGURES)}")
        png, err = env.app.quatnav_figures[name]
        if err:  # already reported as a warning when the figure was made
            para = nodes.paragraph(text=f"[figure {name} missing: {command_line(name)} failed "
                                        "when the documentation was built]")
            return [nodes.warning("", para)]
        self.arguments[0] = "/" + os.path.relpath(png, env.srcdir)
        self.options.setdefault("alt", f"figure made by {command_line(name)}")
        # the page's width, and a link to the image at its own size (Sphinx links a scaled image)
        self.options.setdefault("width", "100%")
        made_by = f"Made by `{command_line(name)}`."
        if self.content:  # the command ends the caption (the content's first paragraph)
            end = next((i for i, line in enumerate(self.content) if not line.strip()), len(self.content))
            self.content.insert(end, StringList([made_by]))
        else:
            self.content = StringList([made_by])
        return super().run()


def setup(app):
    app.add_config_value("quatnav_figures_dir", None, "env")
    app.connect("builder-inited", _generate)
    app.add_directive("quatnav-figure", QuatnavFigure)
    return {"version": "1", "parallel_read_safe": True, "parallel_write_safe": True}
