# %% [markdown]
# # tyrefit tutorial: from rig records to a diagnosed Magic Formula tyre and a vehicle simulation
#
# A script in the "percent" format: run it with `python docs/tutorial.py [OUT_DIR]`, or open it in
# Jupyter as a notebook (jupytext reads the `# %%` cells). The test suite runs it
# (`tests/test_docs_tutorial.py`), so every line below works with this version of tyrefit.
#
# The data are the bundled TTC-style records of a passenger-car tyre: a cornering record (slip-angle
# sweeps at several loads, cambers and pressures) and a drive/brake record (slip-ratio sweeps at a few
# slip angles), in the FSAE TTC `.dat` layout with SAE signs. **They are synthetic**, made by the seeded
# generator `tyrefit.synthetic.ttc_drivebrake` from a published MF 6.1 tyre (see `data/README.md`).

# %%
import sys
from pathlib import Path

import matplotlib

if __name__ == "__main__" and "ipykernel" not in sys.modules:
    matplotlib.use("Agg")  # a script writes figures to files; a notebook shows them inline
import matplotlib.pyplot as plt

import tyrefit as tf

OUT = Path(sys.argv[1]) if len(sys.argv) > 1 and not sys.argv[1].startswith("-") else Path("tutorial_out")
OUT.mkdir(parents=True, exist_ok=True)

# %% [markdown]
# ## 1. Read the records
# `read_data` reads CSV with unit headers, TYDEX `.tdx` and TTC `.dat` files into SI units and ISO-W
# signs; `convention="sae"` says the file's signs are SAE's (TTC: Fz negative).

# %%
corner = tf.read_data(tf.datasets.path("ttc_mf61/cornering.dat"), convention="sae")
drive = tf.read_data(tf.datasets.path("ttc_mf61/drivebrake.dat"), convention="sae")
print(corner.kind, len(corner.df), "samples,", corner.n_runs, "sweeps")
print(drive.kind, len(drive.df), "samples,", drive.n_runs, "sweeps")

# %% [markdown]
# ## 2. Diagnose what a simple model misses
# `diagnose` starts from a base PAC89 lateral model and adds, one at a time, the physical effects
# (camber, pressure, load-dependent friction, ...) that held-out sweeps confirm. Each accepted effect
# comes with its physics; the waterfall shows the error falling towards the noise floor.

# %%
dg = tf.diagnose(corner, rated_load=6000.0)
print(dg.summary())
ax = dg.plot_waterfall()
ax.figure.savefig(OUT / "waterfall.png", dpi=110)

# %% [markdown]
# ## 3. Fit one Magic Formula 6.1 tyre to both records
# The fit varies every coefficient the records identify (the rest are held, and said so) and is
# checked against the tyre contract: physical over every range the file declares, not only at the
# samples. `effects=` instead continues diagnose's waterfall in MF 6.1: its start model plus the
# coefficients of the accepted effects only.

# %%
mf = tf.fit([corner, drive], model="mf61")
print(mf.summary())
waterfall = tf.fit([corner, drive], model="mf61", effects=dg.accepted)
print(f"Fy RMSE {mf.rmse:.0f} N with every identifiable coefficient; {waterfall.rmse:.0f} N with diagnose's "
      f"start model + {', '.join(dg.accepted) or 'no effects'}")
assert mf.contract() == [], mf.contract()
plt.close("all")
axes = mf.plot()  # one panel per condition level, loads as lines, on pyplot
plt.gcf().savefig(OUT / "fit.png", dpi=90)
tir = mf.tyre.to_tir(OUT / "passenger_mf61.tir")
print("wrote", tir)

# %% [markdown]
# ## 4. Use the tyre file
# Any tyre file tyrefit reads (PAC89, MF 5.2/6.1/6.2, Chrono JSON) evaluates the same way.

# %%
import numpy as np  # noqa: E402

tyre = tf.read_tyre(tir)
f = tyre.forces(fz=np.full(3, 4000.0), slip_angle=np.radians([-4.0, 0.0, 4.0]))
print("Fy at 4 kN and -4, 0, +4 deg:", np.round(f["fy"], 1), "N")

# %% [markdown]
# ## 5. Simulate a vehicle on it
# The emergency braking of Pham et al. 2025 on the default car, then a steady-state constant-radius
# ramp to the limit. Every run says where the tyres worked against the envelope they were fitted in.

# %%
brake = tf.simulate("braking", front=tyre, rear=tyre, vehicle="ev")
print("stopping distances [m]:", [round(r["stopping_distance_m"], 1) for r in brake.json["rows"]])
ramp = tf.simulate("ramp", front=tyre, rear=tyre, vehicle="ev")
print(f"understeer gradient {ramp.json['understeer_gradient_deg_per_g']:.2f} deg/g, "
      f"lateral limit {ramp.json['lateral_limit_g']:.2f} g, "
      f"outside the fitted envelope {100 * ramp.json['tyres']['front']['outside_envelope']:.0f} % of the time")
