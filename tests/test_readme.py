"""The README's Python example runs as written (every ```python block, in order, in one
namespace), the values its comments promise are what it gives, and its links into the
documentation lead to files that exist. The examples of the docs' pages run in
tests/test_docs.py."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
README = ROOT / "README.md"


def python_blocks() -> list[str]:
    return re.findall(r"^```python\n(.*?)^```", README.read_text(), flags=re.S | re.M)


def test_the_readme_is_a_front_page_with_its_example():
    text = README.read_text()
    assert len(text.splitlines()) <= 200
    assert len(python_blocks()) >= 1
    # The two set-up commands come first, right under the title.
    first = re.search(r"^```bash\n(.*?)^```", text, flags=re.S | re.M)
    assert text.index(first.group(0)) == len("# impulse2d\n\n")
    assert ".[rl]" in first.group(1) and ".[test]" in first.group(1)


@pytest.mark.filterwarnings("ignore::DeprecationWarning")
def test_every_python_block_runs_and_gives_what_it_says(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)  # anything an example writes lands here
    namespace: dict = {}
    for block in python_blocks():
        exec(compile(block, str(README), "exec"), namespace)
    # "steps each world took: [58]" and "False, 0 (the pocket), -1"
    assert list(namespace["steps"]) == [58]
    ball = namespace["ball"]
    assert (bool(ball.enabled), int(ball.sensed), int(ball.first_contact)) == (False, 0, -1)
    # "(1024, 2): one row per world"
    assert namespace["batch"].bodies[0].position.shape == (1024, 2)


def test_the_readme_links_lead_to_files():
    links = re.findall(r"\]\(([^)#\s]+)(?:#[^)]*)?\)", README.read_text())
    local = [link for link in links if "://" not in link]
    assert any(link.startswith("docs/") for link in local)
    missing = [link for link in local if not (ROOT / link).exists()]
    assert not missing, missing
