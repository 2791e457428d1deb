"""A leaderboard's Markdown as one self-contained HTML page: figures inline, tables sortable.

:func:`html_page` converts a board's Markdown (:func:`ioc_bench.runner.leaderboard.markdown`)
with Python-Markdown and returns a page that needs nothing beside it and no network: every
local figure under the board's folder is inlined as a ``data:`` URI, the style and the
table-sorting script are inline, and a Content-Security-Policy keeps the browser from
fetching anything (images only from ``data:``, the one script by its hash).

The Markdown is built from result records that can hold user strings (algorithm names,
failure reasons), so raw HTML in it is text: Python-Markdown's raw-HTML block and inline
handling are switched off, which makes ``<script>`` in a table cell come out as
``&lt;script&gt;`` (code spans are escaped once, as always). Link targets keep only the
``http``, ``https`` and ``mailto`` schemes and relative paths (a ``javascript:`` link loses
its target, keeping its text); images are read only from files under the folder.
"""

from __future__ import annotations

import base64
import hashlib
import html
import os
import re
import xml.etree.ElementTree as etree
from pathlib import Path, PurePosixPath, PureWindowsPath
from urllib.parse import unquote, urlsplit

import markdown as python_markdown
from markdown.extensions import Extension
from markdown.treeprocessors import Treeprocessor

__all__ = ["html_page"]

# Figure types inlined, by file suffix (lower case).
_MIME = {
    ".png": "image/png",
    ".svg": "image/svg+xml",
    ".jpg": "image/jpeg",
    ".jpeg": "image/jpeg",
    ".gif": "image/gif",
    ".webp": "image/webp",
}
_LINK_SCHEMES = frozenset({"http", "https", "mailto"})
_SCHEME = re.compile(r"^([A-Za-z][A-Za-z0-9+.\-]*):")
# Browsers drop ASCII whitespace and control characters from a URL before reading its
# scheme ("java\tscript:" is "javascript:"), so the checks do too.
_IGNORED_IN_URL = re.compile(r"[\x00-\x20\x7f]")
# A cell "is a number" when it starts with one, optionally after "[" or "(": 0.0123,
# 1.2e-05, [0.01, 0.02], 6/12 / 0.001. The sorting script uses the same rule.
_LEADING_NUMBER = re.compile(r"^\s*[\[(]?\s*[-+]?(?:\d+(?:\.\d*)?|\.\d+)(?:[eE][-+]?\d+)?")
_MISSING = frozenset({"", "-", "\u2013", "\u2014", "n/a", "na", "nan", "none"})


def html_page(markdown_text: str, folder: str | os.PathLike, title: str) -> str:
    """The self-contained HTML page of a board.

    Args:
        markdown_text: the board's Markdown (headings, paragraphs, pipe tables, lists,
            images, links). Raw HTML in it is shown as text, never interpreted.
        folder: the board's folder: relative image paths are read from it, and only from
            it (an absolute path, a path with ``..`` or one leading out of it through a
            symlink is not read). Relative links are kept as they are, relative to the page.
        title: the page's ``<title>`` (escaped).

    Returns:
        One HTML document. An image whose file exists under ``folder`` (png, svg, jpg, gif,
        webp) becomes a ``data:`` URI; any other image becomes a visible note with its alt
        text ("(figure missing: path)" or "(figure not embedded: src)"). Every table sits in
        a scrolling box and sorts by a click on a header (numbers by their first number,
        ``n/a`` and ``-`` last, ``aria-sort`` and an arrow on the sorted header); columns of
        numbers are right-aligned in monospace. The page references nothing outside itself
        except the links the Markdown holds.
    """
    converter = python_markdown.Markdown(
        extensions=["tables", "toc", _BoardExtension(Path(folder))],
        output_format="html",
    )
    body = converter.convert(markdown_text)
    script_hash = base64.b64encode(hashlib.sha256(_SCRIPT.encode()).digest()).decode()
    policy = (
        "default-src 'none'; img-src data:; style-src 'unsafe-inline'; "
        f"script-src 'sha256-{script_hash}'; base-uri 'none'; form-action 'none'"
    )
    return (
        "<!DOCTYPE html>\n"
        '<html lang="en">\n<head>\n<meta charset="utf-8">\n'
        f'<meta http-equiv="Content-Security-Policy" content="{policy}">\n'
        '<meta name="viewport" content="width=device-width, initial-scale=1">\n'
        f"<title>{html.escape(title)}</title>\n"
        f"<style>{_STYLE}</style>\n"
        "</head>\n<body>\n<main>\n"
        f"{body}\n"
        "</main>\n"
        f"<script>{_SCRIPT}</script>\n"
        "</body>\n</html>\n"
    )


class _BoardExtension(Extension):
    """Raw HTML as text; images inlined from the folder; links sanitised; tables marked."""

    def __init__(self, folder: Path) -> None:
        super().__init__()
        self.folder = folder

    def extendMarkdown(self, md: python_markdown.Markdown) -> None:
        md.preprocessors.deregister("html_block")
        md.inlinePatterns.deregister("html")
        # After the inline patterns (20) have made the images and links.
        md.treeprocessors.register(_BoardTreeprocessor(md, self.folder), "ioc_bench_board", 1)


class _BoardTreeprocessor(Treeprocessor):
    def __init__(self, md: python_markdown.Markdown, folder: Path) -> None:
        super().__init__(md)
        self.folder = folder

    def run(self, root: etree.Element) -> None:
        parents = {child: parent for parent in root.iter() for child in parent}
        for element in list(root.iter()):
            if element.tag == "img":
                self._image(element)
            elif element.tag == "a":
                _sanitise_link(element)
            elif element.tag == "table":
                _mark_numeric_columns(element)
                _wrap(element, parents[element])

    def _image(self, img: etree.Element) -> None:
        src = img.get("src", "")
        alt = img.get("alt", "")
        uri, note = _embedded(src, self.folder)
        if uri is not None:
            img.set("src", uri)
            return
        # The element becomes the note in place (its tail, the text after it, stays).
        title = img.get("title")
        img.attrib.clear()
        img.tag = "span"
        img.set("class", "figure-missing")
        if title:
            img.set("title", title)
        img.text = f"{alt} ({note})" if alt else f"({note})"


def _embedded(src: str, folder: Path) -> tuple[str | None, str]:
    """(``data:`` URI of the figure, None) if ``src`` names a readable file under ``folder``;
    else (None, why not)."""
    cleaned = _IGNORED_IN_URL.sub("", src)
    if not cleaned:
        return None, "figure not embedded: no path"
    if _SCHEME.match(cleaned) or cleaned.startswith(("//", "\\\\")):
        return None, f"figure not embedded: {src}"
    path = unquote(urlsplit(cleaned).path)
    parts = re.split(r"[/\\]", path)
    if (
        not path
        or "\x00" in path
        or ".." in parts
        or PurePosixPath(path).is_absolute()
        or PureWindowsPath(path).is_absolute()
        or PureWindowsPath(path).drive
        or path.startswith(("/", "\\"))
    ):
        return None, f"figure not embedded: {src}"
    mime = _MIME.get(PurePosixPath(path).suffix.lower())
    if mime is None:
        return None, f"figure not embedded: {src}"
    try:
        base = folder.resolve()
        target = (base / path).resolve()
    except (OSError, RuntimeError):
        return None, f"figure missing: {src}"
    if not target.is_relative_to(base):  # a symlink out of the folder
        return None, f"figure not embedded: {src}"
    try:
        data = target.read_bytes()
    except OSError:  # missing, a folder, unreadable
        return None, f"figure missing: {src}"
    return f"data:{mime};base64,{base64.b64encode(data).decode('ascii')}", ""


def _sanitise_link(a: etree.Element) -> None:
    href = a.get("href")
    if href is None:
        return
    scheme = _SCHEME.match(_IGNORED_IN_URL.sub("", href))
    if scheme is not None and scheme.group(1).lower() not in _LINK_SCHEMES:
        del a.attrib["href"]


def _cell_text(cell: etree.Element) -> str:
    return "".join(cell.itertext()).strip()


def _mark_numeric_columns(table: etree.Element) -> None:
    """Class ``num`` on every header and cell of a column whose cells all start with a
    number (missing ones aside) and at least one does."""
    rows = list(table.iter("tr"))
    body_rows = [row for section in table.findall("tbody") for row in section.findall("tr")]
    if not body_rows:
        return
    width = max(len(row) for row in rows)
    for column in range(width):
        texts = [_cell_text(row[column]) for row in body_rows if column < len(row)]
        present = [text for text in texts if text.lower() not in _MISSING]
        if present and all(_LEADING_NUMBER.match(text) for text in present):
            for row in rows:
                if column < len(row):
                    cell = row[column]
                    classes = cell.get("class")
                    cell.set("class", f"{classes} num" if classes else "num")


def _wrap(table: etree.Element, parent: etree.Element) -> None:
    """Put the table in a ``div.table-wrap`` (scrolls sideways and down, header sticky)."""
    index = list(parent).index(table)
    wrapper = etree.Element("div", {"class": "table-wrap"})
    wrapper.tail = table.tail
    table.tail = None
    parent.remove(table)
    wrapper.append(table)
    parent.insert(index, wrapper)


_STYLE = """
:root { color-scheme: light dark; --line: #8884; --zebra: #8881; --head: Canvas; }
body { font-family: system-ui, -apple-system, "Segoe UI", Roboto, sans-serif; line-height: 1.5;
  max-width: 80rem; margin: 0 auto; padding: 1rem 1.5rem 3rem; }
h1, h2, h3 { line-height: 1.25; }
code { font-family: ui-monospace, SFMono-Regular, Menlo, Consolas, monospace; font-size: 0.9em;
  background: var(--zebra); padding: 0.1em 0.25em; border-radius: 3px; overflow-wrap: anywhere; }
img { max-width: 100%; height: auto; }
.figure-missing { display: inline-block; padding: 0.25em 0.5em; border: 1px dashed var(--line);
  font-style: italic; }
.table-wrap { overflow: auto; max-height: 85vh; margin: 1rem 0; border: 1px solid var(--line); }
table { border-collapse: collapse; font-size: 0.85rem; }
th, td { padding: 0.3em 0.6em; border-bottom: 1px solid var(--line); text-align: left;
  vertical-align: top; }
thead th { position: sticky; top: 0; z-index: 1; background: var(--head);
  border-bottom: 2px solid var(--line); white-space: nowrap; }
tbody tr:nth-child(even) { background: var(--zebra); }
tbody tr:hover { background: #8883; }
td.num, th.num { text-align: right; }
td.num { font-family: ui-monospace, SFMono-Regular, Menlo, Consolas, monospace; white-space: nowrap; }
th button { font: inherit; color: inherit; background: none; border: 0; padding: 0; margin: 0;
  text-align: inherit; cursor: pointer; }
th button:focus-visible { outline: 2px solid Highlight; }
th .sort-arrow { margin-left: 0.3em; opacity: 0.4; }
th[aria-sort] .sort-arrow { opacity: 1; }
"""

# Clicking a header sorts its table's body by that column: ascending, then descending. A
# column whose present cells all start with a number sorts by that number; others as text
# (numbers inside text in order: noise-2 before noise-10). Missing cells (empty, -, n/a)
# stay last either way; ties keep their order.
_SCRIPT = r"""
(function () {
  "use strict";
  var NUMBER = /^\s*[\[(]?\s*([-+]?(?:\d+(?:\.\d*)?|\.\d+)(?:[eE][-+]?\d+)?)/;
  var MISSING = ["", "-", "\u2013", "\u2014", "n/a", "na", "nan", "none"];
  var ARROWS = {ascending: "\u25B2", descending: "\u25BC", none: "\u2195"};
  function text(cell) { return cell ? cell.textContent.trim() : ""; }
  function missing(value) { return MISSING.indexOf(value.toLowerCase()) >= 0; }
  function sortBy(table, column, th) {
    var body = table.tBodies[0];
    if (!body) { return; }
    var direction = th.getAttribute("aria-sort") === "ascending" ? "descending" : "ascending";
    var rows = Array.prototype.slice.call(body.rows);
    var keyed = rows.map(function (row, index) {
      var value = text(row.cells[column]);
      var match = NUMBER.exec(value);
      return {row: row, index: index, value: value, missing: missing(value),
              number: match ? parseFloat(match[1]) : NaN};
    });
    var numeric = keyed.some(function (k) { return !k.missing; }) &&
      keyed.every(function (k) { return k.missing || !isNaN(k.number); });
    var sign = direction === "ascending" ? 1 : -1;
    keyed.sort(function (a, b) {
      if (a.missing !== b.missing) { return a.missing ? 1 : -1; }
      var order = 0;
      if (!a.missing) {
        order = numeric ? (a.number < b.number ? -1 : a.number > b.number ? 1 : 0)
                        : a.value.localeCompare(b.value, undefined, {numeric: true, sensitivity: "base"});
      }
      return order !== 0 ? sign * order : a.index - b.index;
    });
    keyed.forEach(function (k) { body.appendChild(k.row); });
    Array.prototype.forEach.call(table.tHead.rows[0].cells, function (other) {
      var state = other === th ? direction : "none";
      if (other === th) { other.setAttribute("aria-sort", direction); } else { other.removeAttribute("aria-sort"); }
      var arrow = other.querySelector(".sort-arrow");
      if (arrow) { arrow.textContent = ARROWS[state]; }
    });
  }
  Array.prototype.forEach.call(document.querySelectorAll("table"), function (table) {
    if (!table.tHead || !table.tHead.rows.length || !table.tBodies.length) { return; }
    Array.prototype.forEach.call(table.tHead.rows[0].cells, function (th, column) {
      var button = document.createElement("button");
      button.type = "button";
      button.title = "Sort by this column";
      while (th.firstChild) { button.appendChild(th.firstChild); }
      var arrow = document.createElement("span");
      arrow.className = "sort-arrow";
      arrow.setAttribute("aria-hidden", "true");
      arrow.textContent = ARROWS.none;
      button.appendChild(arrow);
      th.appendChild(button);
      button.addEventListener("click", function () { sortBy(table, column, th); });
    });
  });
})();
"""
