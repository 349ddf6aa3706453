"""HTML reports are self-contained: figures embedded, text escaped."""

import matplotlib.pyplot as plt
import pandas as pd

from tyrefit.io.report import Report


def test_report_embeds_figures_and_escapes(tmp_path):
    r = Report("Fit <report>")
    r.h2("Table").table(pd.DataFrame({"name": ["a0"], "value": [1.65]}))
    fig, ax = plt.subplots()
    ax.plot([0, 1], [0, 1])
    r.figure(fig, "a line")
    path = r.save(tmp_path)
    html = path.read_text()
    assert "Fit &lt;report&gt;" in html
    assert "data:image/png;base64," in html
    assert "<td>a0</td><td>1.65</td>" in html
    assert "src=\"http" not in html  # nothing fetched when opened
