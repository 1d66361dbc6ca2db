"""Sphinx configuration of impulse2d's documentation site.

    pip install -e ".[docs]"
    python -m sphinx -W --keep-going -b html docs docs/_build/html

Why Sphinx (with the furo theme and MyST Markdown pages): it is what the projects
impulse2d sits beside document with. Gymnasium builds its site with Sphinx, furo and
MyST, and so its users know the layout; Stable-Baselines3 and pymunk document with Sphinx
too. autodoc reads the docstrings the package already has, so the API reference is
generated, not written twice, and every page stays plain Markdown that GitHub renders as
well. intersphinx is left out on purpose: the build runs where there is no network.

Each environment's page takes its specification from the env class's docstring, as
Gymnasium's site does: those docstrings are Markdown in Gymnasium's sections, so a page
names the class in a ```{docstring} fence and ``_insert_docstrings`` puts the
docstring's text there before MyST parses the page (its ``##`` sections one level down).
In the API reference autodoc, which reads docstrings as reStructuredText, shows those
classes' first line and a link to their page (``_markdown_docstrings``).
"""

from __future__ import annotations

import importlib
import inspect
import re
from typing import Any

import impulse2d

project = "impulse2d"
author = "the impulse2d authors"
copyright = "impulse2d authors"
release = impulse2d.__version__
version = release

extensions = ["myst_parser", "sphinx.ext.autodoc", "sphinx.ext.viewcode"]
source_suffix = {".md": "markdown"}
root_doc = "index"
# docs/ also holds the README's pictures and a script that makes them.
exclude_patterns = ["_build", "**/__pycache__", "env_gifs.py", "*.py", "Thumbs.db", ".DS_Store"]

myst_heading_anchors = 3  # `page.md#a-section` links, as GitHub makes them
myst_enable_extensions = ["colon_fence"]

html_theme = "furo"
html_title = f"impulse2d {release}"
html_static_path: list[str] = []
pygments_style = "sphinx"
pygments_dark_style = "monokai"

autodoc_member_order = "bysource"
autodoc_default_options: dict[str, object] = {}
autodoc_typehints = "signature"
autoclass_content = "class"
# Methods without a docstring of their own stay undocumented rather than showing
# gymnasium's or SB3's (reST of another project's conventions).
autodoc_inherit_docstrings = False

# Docstrings written in Markdown (the env specifications): the page each one lives on.
MARKDOWN_DOCSTRINGS = {
    "impulse2d.envs.pool.Pool2DEnv": "envs/pool2d",
    "impulse2d.envs.slingshot.Slingshot2DEnv": "envs/slingshot2d",
}
_FENCE = re.compile(r"^```\{docstring\} *(\S+)\n```[ \t]*$", re.MULTILINE)


def _resolve(name: str) -> Any:
    module, _, attribute = name.rpartition(".")
    return getattr(importlib.import_module(module), attribute)


def _insert_docstrings(app: Any, docname: str, source: list[str]) -> None:
    """Replace each ```{docstring} NAME fence with NAME's docstring, as Markdown, its
    headings one level down (the page's own sections are ``##``)."""

    def text(match: re.Match[str]) -> str:
        doc = inspect.cleandoc(_resolve(match.group(1)).__doc__ or "")
        return re.sub(r"^(#+) ", r"#\1 ", doc, flags=re.MULTILINE)

    source[0] = _FENCE.sub(text, source[0])


def _markdown_docstrings(
    app: Any, what: str, name: str, obj: Any, options: Any, lines: list[str]
) -> None:
    """autodoc reads docstrings as reStructuredText: for the Markdown ones, their first
    line and where the whole specification is."""
    page = MARKDOWN_DOCSTRINGS.get(name)
    if page is not None and what == "class" and lines:
        first = lines[0]
        lines[:] = [first, "", f"The full specification: :doc:`/{page}`.", ""]


def _usage_blocks(app: Any, what: str, name: str, obj: Any, options: Any, lines: list[str]) -> None:
    """The commands' module docstrings open with usage lines indented under the summary:
    show them as literal blocks (command lines), not as quoted prose."""
    if what != "module" or not name.startswith("impulse2d.agents."):
        return
    out: list[str] = []
    for i, line in enumerate(lines):
        starts_block = line.startswith("    ") and i > 0 and not lines[i - 1].strip()
        before = next((x for x in reversed(out[:-1]) if x.strip()), "")
        if starts_block and not before.startswith("    ") and not before.endswith("::"):
            out[-1:] = ["", "::", ""]
        out.append(line)
    lines[:] = out


def setup(app: Any) -> dict[str, Any]:
    app.connect("source-read", _insert_docstrings)
    app.connect("autodoc-process-docstring", _markdown_docstrings)
    app.connect("autodoc-process-docstring", _usage_blocks)
    return {"parallel_read_safe": True, "parallel_write_safe": True}
