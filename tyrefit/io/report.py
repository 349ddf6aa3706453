"""Self-contained HTML reports: headings, prose, tables and embedded figures.

A :class:`Report` collects blocks and renders one HTML file with every figure
embedded as a base64 PNG, so a report can be mailed or archived as one file.
Used by every command that takes ``--report DIR``.
"""

from __future__ import annotations

import base64
import html
import io
import json
import os
from collections.abc import Iterable, Mapping, Sequence
from pathlib import Path
from .outputs import write_text

__all__ = ["Report", "fig_to_png", "esc"]

_CSS = """
body{font-family:system-ui,-apple-system,Segoe UI,Helvetica,Arial,sans-serif;max-width:1150px;margin:2em auto;
padding:0 1em;color:#1b1b1b;line-height:1.45}
h1{border-bottom:2px solid #345;padding-bottom:.2em}h2{margin-top:1.6em;color:#234}
table{border-collapse:collapse;margin:.6em 0;font-size:.9em}
th,td{border:1px solid #ccc;padding:.25em .6em;text-align:right}th{background:#eef2f6}
td:first-child,th:first-child{text-align:left}
figure{margin:1em 0}figcaption{font-size:.88em;color:#444}
.note{background:#f6f8fa;border-left:4px solid #89a;padding:.5em 1em}
.warn{background:#fff6e5;border-left:4px solid #e0a030;padding:.5em 1em}
.ok{color:#1a7f37}.bad{color:#b42318}code{background:#f2f2f2;padding:0 .2em}
"""


def esc(text: object) -> str:
    """HTML-escape ``text``."""
    return html.escape(str(text))


def fig_to_png(fig, dpi: int = 110) -> bytes:
    """Render a matplotlib figure to PNG bytes (a pyplot-managed figure is closed afterwards).

    Library figures are plain :class:`matplotlib.figure.Figure` objects, which
    render without pyplot and never touch the user's backend (inline Jupyter
    figures keep working); a figure made with pyplot is closed so that it is
    not shown again or kept alive by pyplot.
    """
    import sys

    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=dpi, bbox_inches="tight")
    if "matplotlib.pyplot" in sys.modules and getattr(fig.canvas, "manager", None) is not None:
        sys.modules["matplotlib.pyplot"].close(fig)
    return buf.getvalue()


def _fmt(v: object, digits: int) -> str:
    if isinstance(v, float):
        if v != v:  # NaN
            return "–"
        a = abs(v)
        if a != 0 and (a >= 1e5 or a < 1e-3):
            return f"{v:.{digits}g}"
        return f"{v:.{digits}g}" if a >= 1e3 else f"{v:.{digits}g}"
    return str(v)


class Report:
    """An HTML report built block by block.

    Examples
    --------
    >>> r = Report("PAC89 fit")
    >>> r.h2("Coefficients"); r.table([{"name": "a0", "value": 1.6}])
    >>> r.save("reports/fit")  # writes reports/fit/index.html
    """

    def __init__(self, title: str, subtitle: str | None = None):
        self.title = title
        self.blocks: list[str] = []
        if subtitle:
            self.p(subtitle)

    # -- blocks ---------------------------------------------------------------
    def h2(self, text: str) -> "Report":
        self.blocks.append(f"<h2>{esc(text)}</h2>")
        return self

    def h3(self, text: str) -> "Report":
        self.blocks.append(f"<h3>{esc(text)}</h3>")
        return self

    def p(self, text: str, cls: str | None = None) -> "Report":
        c = f' class="{cls}"' if cls else ""
        self.blocks.append(f"<p{c}>{esc(text)}</p>")
        return self

    def raw(self, html_text: str) -> "Report":
        """Append trusted HTML (already escaped by the caller)."""
        self.blocks.append(html_text)
        return self

    def bullets(self, items: Iterable[str]) -> "Report":
        self.blocks.append("<ul>" + "".join(f"<li>{esc(i)}</li>" for i in items) + "</ul>")
        return self

    def link(self, href: str, text: str) -> "Report":
        self.blocks.append(f'<p><a href="{esc(href)}">{esc(text)}</a></p>')
        return self

    def table(self, rows, columns: Sequence[str] | None = None, digits: int = 4, caption: str | None = None) -> "Report":
        """A table from a DataFrame, a list of dicts or a list of sequences."""
        try:
            import pandas as pd

            if isinstance(rows, pd.DataFrame):
                columns = list(rows.columns) if columns is None else list(columns)
                rows = rows[columns].to_dict("records")
        except ImportError:  # pragma: no cover
            pass
        rows = list(rows)
        if rows and isinstance(rows[0], Mapping):
            columns = list(columns or rows[0].keys())
            body = [[r.get(c, "") for c in columns] for r in rows]
        else:
            body = [list(r) for r in rows]
            columns = list(columns or [])
        out = ["<table>"]
        if caption:
            out.append(f"<caption>{esc(caption)}</caption>")
        if columns:
            out.append("<tr>" + "".join(f"<th>{esc(c)}</th>" for c in columns) + "</tr>")
        for r in body:
            out.append("<tr>" + "".join(f"<td>{esc(_fmt(v, digits))}</td>" for v in r) + "</tr>")
        out.append("</table>")
        self.blocks.append("".join(out))
        return self

    def figure(self, fig, caption: str = "", dpi: int = 110) -> "Report":
        """Embed a matplotlib figure (closed afterwards)."""
        data = base64.b64encode(fig_to_png(fig, dpi)).decode("ascii")
        cap = f"<figcaption>{esc(caption)}</figcaption>" if caption else ""
        self.blocks.append(f'<figure><img alt="{esc(caption)}" src="data:image/png;base64,{data}" '
                           f'style="max-width:100%">{cap}</figure>')
        return self

    def json_block(self, obj, title: str = "JSON") -> "Report":
        self.blocks.append(f"<details><summary>{esc(title)}</summary><pre>{esc(json.dumps(obj, indent=2, default=float))}</pre></details>")
        return self

    # -- output ---------------------------------------------------------------
    def html(self) -> str:
        return (
            "<!DOCTYPE html><html><head><meta charset='utf-8'>"
            f"<title>{esc(self.title)}</title><style>{_CSS}</style></head><body>"
            f"<h1>{esc(self.title)}</h1>" + "\n".join(self.blocks) + "</body></html>\n"
        )

    def _repr_html_(self) -> str:
        return "\n".join(self.blocks)

    def save(self, directory: str | os.PathLike, name: str = "index.html", force: bool = True) -> Path:
        """Write ``directory/name`` atomically and return its path."""
        return write_text(Path(directory) / name, self.html(), force=force)  # creates the folder
