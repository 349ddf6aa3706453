"""Seeded generators of the **synthetic** example data in ``data/``.

Real rig measurements cannot be shipped, so every bundled data set is made
here by a documented, seeded generator whose physics and parameters are in
its module docstring.  Every file they write starts with a
``# synthetic: ...`` line; nothing generated here is a measurement.

``python -m tyrefit.synthetic --out data`` regenerates everything.
"""

#: generator modules, each exposing ``generate(out_dir) -> list[Path]``,
#: and the ``data/`` sub-folder each one writes
GENERATORS = {
    "ttc": "tyrefit.synthetic.ttc",
    "ttc_mf61": "tyrefit.synthetic.ttc_drivebrake",
    "truck": "tyrefit.synthetic.truck",
    "passenger": "tyrefit.synthetic.passenger",
    "sim": "tyrefit.synthetic.vehicle_tyres",
    "slip": "tyrefit.synthetic.slip",
    "brush": "tyrefit.synthetic.camber_brush",
}
