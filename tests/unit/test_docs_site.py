"""The API reference (issue 34 item 5): mkdocs.yml and docs/api/ build with warnings as errors
(mkdocstrings reads the docstrings from the sources, no import of rvsim), and every call the
top level offers has its entry."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
PAGES = ROOT / "docs" / "api"


def test_every_top_level_call_is_in_the_reference():
    import rvsim

    text = "\n".join(p.read_text(encoding="utf-8") for p in sorted(PAGES.glob("*.md")))
    documented = set(re.findall(r"^::: (rvsim[\w.]*)", text, flags=re.M))
    missing = [f"rvsim.{module}.{attribute}" for name, (module, attribute) in rvsim._LAZY.items()
               if not name.isupper() and f"rvsim.{module}.{attribute}" not in documented]
    assert not missing


def test_the_reference_builds_without_a_warning(tmp_path):
    pytest.importorskip("mkdocstrings_handlers.python", reason="the docs extra: "
                        "pip install -e .[docs]")
    from mkdocs.commands.build import build
    from mkdocs.config import load_config

    config = load_config(str(ROOT / "mkdocs.yml"), site_dir=str(tmp_path / "site"),
                         strict=True)
    build(config)                             # raises mkdocs's Abort on a warning (strict)
    page = (tmp_path / "site" / "quasistatic" / "index.html").read_text(encoding="utf-8")
    assert "rvsim.quasistatic.efficiency.efficiency" in page and "EfficiencyResult" in page
    assert ":func:" not in page and ":class:" not in page      # docs/api_hooks.py
