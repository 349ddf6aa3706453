"""A notebook, as a script: only the public API of ``import tyrefit as tf`` (DESIGN, "The Python API").

From the bundled truck data and a TTC-style cornering + drive/brake pair to exported tyre files, figures
registered with pyplot, and HTML for a notebook; then the same data and options through the command line
give the same tyre file, byte for byte (the header's date line aside).
"""

from __future__ import annotations

import re

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402

import tyrefit as tf  # noqa: E402
from tyrefit.cli import main  # noqa: E402


def _body(path) -> str:
    """The file without lines that name the date or the output path (those differ between two writes)."""
    return "\n".join(ln for ln in open(path).read().splitlines()
                     if not re.search(r"\b(19|20)\d\d-\d\d-\d\d\b|DATE|written", ln))


def test_the_public_names_are_exported():
    for name in ("read_data", "read_tyre", "fit", "diagnose", "compare", "simulate", "datasets"):
        assert name in tf.__all__ and getattr(tf, name) is not None
    assert tf.datasets.path("truck/tyre_a_dynamic.csv").is_file()
    assert "ttc_mf61/cornering.dat" in tf.datasets.names()
    with pytest.raises(tf.errors.DataError if hasattr(tf, "errors") else Exception, match="did you mean"):
        tf.datasets.path("tyre_a_dynamic.csv")


def test_notebook_truck_pac89(tmp_path):
    ds = tf.read_data(tf.datasets.path("truck/tyre_a_dynamic.csv"))
    res = tf.fit(ds, model="pac89", cost="l1", size="385/65R22.5", rated_load=41678)
    assert "RMSE" in res.summary() or "rmse" in res.summary().lower()
    assert "<table" in res._repr_html_()
    frame = res.to_frame() if hasattr(res, "to_frame") else None
    plt.close("all")
    ax = res.plot()
    assert plt.get_fignums(), "the figure is registered with pyplot (a script's plt.show() shows it)"
    assert np.atleast_1d(ax).size >= 1
    plt.close("all")
    a = res.tyre.to_tir(tmp_path / "a.tir")
    res.tyre.to_json(tmp_path / "a.json")
    assert (tmp_path / "a.json").is_file()
    # the command line on the same data and options: the same tyre
    cli = tmp_path / "cli.tir"
    assert main(["fit", str(tf.datasets.path("truck/tyre_a_dynamic.csv")), "--cost", "l1", "--size", "385/65R22.5",
                 "--rated-load", "41678", "--out", str(cli)]) == 0
    assert _body(a or tmp_path / "a.tir") == _body(cli)
    assert frame is None or len(frame)


def test_notebook_ttc_pair_mf61(tmp_path):
    corner = tf.read_data(tf.datasets.path("ttc_mf61/cornering.dat"), convention="sae")
    drive = tf.read_data(tf.datasets.path("ttc_mf61/drivebrake.dat"), convention="sae")
    mf = tf.fit([corner, drive], model="mf61")
    assert mf.contract() == []
    assert "<table" in mf._repr_html_()
    plt.close("all")
    axes = mf.plot()
    assert plt.get_fignums() and np.atleast_1d(axes).size >= 2  # one panel per condition level
    plt.close("all")
    out = mf.tyre.to_tir(tmp_path / "mf.tir")
    back = tf.read_tyre(out)
    f = back.forces(fz=[4000.0, 8000.0], slip_angle=np.radians([3.0, -3.0]), slip_ratio=[0.0, 0.05])
    assert np.all(np.isfinite(f["fy"])) and f["fy"][0] < 0 < f["fy"][1]
    cli = tmp_path / "cli.tir"
    assert main(["fit", str(tf.datasets.path("ttc_mf61/cornering.dat")), str(tf.datasets.path("ttc_mf61/drivebrake.dat")),
                 "--convention", "sae", "--model", "mf61", "--out", str(cli)]) == 0
    assert _body(out) == _body(cli)
    with pytest.raises(Exception, match="PAC89"):
        mf.tyre.to_json(tmp_path / "mf.json")
    cmp = tf.compare(back, tf.read_tyre(cli))
    assert cmp.summary()["worst_mean_abs_dmu_over_peak"] < 1e-9
