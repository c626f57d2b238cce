"""Rewrite the generated "how far to trust it" text from src/rvsim/data/trust.csv (issue 34).

    python scripts/trust_box.py            # rewrite README.md and docs/validation.md
    python scripts/trust_box.py --check    # exit 1 if either disagrees with trust.csv
    python scripts/trust_box.py --html     # print the reports' HTML box

The text between the markers of rvsim.analysis.trust (START, END) is replaced; nothing else
in either file is touched.
"""

from __future__ import annotations

import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "src"))

from rvsim.analysis.trust import END, START, readme_section, validation_tables  # noqa: E402

TARGETS = {ROOT / "README.md": readme_section, ROOT / "docs" / "validation.md": validation_tables}


def replaced(text: str, block: str) -> str:
    """``text`` with the part from START to END (markers included) replaced by ``block``."""
    head, start, rest = text.partition(START)
    _, end, tail = rest.partition(END)
    if not start or not end:
        raise SystemExit(f"trust_box: markers {START!r} ... {END!r} not found")
    return head + block + tail


def main(argv: list[str]) -> int:
    if "--html" in argv:
        from rvsim.html import trust_box

        print(trust_box())
        return 0
    stale = []
    for path, render in TARGETS.items():
        text = path.read_text(encoding="utf-8")
        new = replaced(text, render())
        if new != text:
            stale.append(path.relative_to(ROOT))
            if "--check" not in argv:
                path.write_text(new, encoding="utf-8")
    if stale and "--check" in argv:
        print("out of date with src/rvsim/data/trust.csv: " + ", ".join(map(str, stale)))
        return 1
    print(("rewrote " + ", ".join(map(str, stale))) if stale else "up to date")
    return 0


if __name__ == "__main__":
    raise SystemExit(main(sys.argv[1:]))
