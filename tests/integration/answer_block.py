"""Read the block a report opens with (issue 34 item 2) with the standard library's HTML
parser: it must be the first element after the page's heading, hold a table of (quantity,
this run, class / target, verdict) and the "how far to trust this" box."""

from __future__ import annotations

from html.parser import HTMLParser

MAX_BYTES = 1_000_000


class _Reader(HTMLParser):
    def __init__(self):
        super().__init__()
        self.top = []             # (tag, id) of the body's direct children, in order
        self.depth = 0
        self.in_summary = 0
        self.rows, self.cell, self.row = [], None, None
        self.text = []

    def handle_starttag(self, tag, attrs):
        attrs = dict(attrs)
        if tag in ("html", "head", "body", "meta", "title", "style", "img", "br"):
            return
        if self.depth == 0:
            self.top.append((tag, attrs.get("id")))
        self.depth += 1
        if self.in_summary or (tag == "section" and attrs.get("id") == "summary"):
            self.in_summary += 1
            if tag == "tr":
                self.row = []
            elif tag in ("td", "th"):
                self.cell = []

    def handle_endtag(self, tag):
        if tag in ("html", "head", "body", "meta", "title", "style", "img", "br"):
            return
        self.depth -= 1
        if self.in_summary:
            self.in_summary -= 1
            if tag in ("td", "th") and self.row is not None:
                self.row.append("".join(self.cell).strip())
                self.cell = None
            elif tag == "tr" and self.row is not None:
                self.rows.append(self.row)
                self.row = None

    def handle_data(self, data):
        if self.in_summary:
            self.text.append(data)
            if self.cell is not None:
                self.cell.append(data)


def answer(page: str) -> dict:
    """The summary block's rows {quantity: [this run, class / target, verdict]} and its text
    (key ``"text"``), after checking that it opens the page and carries the trust box."""
    assert len(page.encode()) < MAX_BYTES
    reader = _Reader()
    reader.feed(page)
    assert reader.top[0][0] == "h1" and reader.top[1] == ("section", "summary"), reader.top[:3]
    rows = {r[0]: r[1:] for r in reader.rows[1:]}
    assert reader.rows[0] == ["quantity", "this run", "class / target", "verdict"]
    text = " ".join(reader.text)
    assert "How far to trust this" in text and "model vs paper" in text
    return {**rows, "text": text}
