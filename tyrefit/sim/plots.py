"""The paper's panels for the scenarios (Pham et al. 2025, Figs. 7-12) and CSV traces.

Colours as in the paper: orange the base vehicle, blue the low-wear one;
solid lines the front axle, dotted the rear.  Every plot function takes
``ax=None`` and returns the Axes; quantities are shown in display units.
"""

from __future__ import annotations

import numpy as np

from .scenarios import PAPER_TABLE3

__all__ = [
    "BASE_COLOR",
    "LOW_WEAR_COLOR",
    "plot_channel",
    "plot_axle_channel",
    "scenario_figure",
    "braking_figure",
    "traces_frame",
    "ramp_figure",
    "step_steer_figure",
    "braking_turn_figure",
]

BASE_COLOR = "tab:orange"
LOW_WEAR_COLOR = "tab:blue"

#: channel -> (label, scale to display units)
_DISPLAY = {
    "vx": ("speed [km/h]", 3.6),
    "ax": ("acceleration [m/s²]", 1.0),
    "ay": ("lateral acceleration [m/s²]", 1.0),
    "n": ("lateral offset n [m]", 1.0),
    "steer": ("steering angle [deg]", 180.0 / np.pi),
    "steer_driver": ("driver's steering [deg]", 180.0 / np.pi),
    "emission": ("emission [#/s]", 1.0),
    "torque": ("wheel torque [N·m]", 1.0),
    "fy": ("lateral force [kN]", 1e-3),
    "fx": ("longitudinal force [kN]", 1e-3),
}


def _ax(ax):
    if ax is None:
        import matplotlib
        from matplotlib.figure import Figure

        ax = Figure(figsize=(6, 3.5)).subplots()
    return ax


def _x(res, j, by):
    m = res.member(j, ["s"])
    return (m["s"], "distance along the path [m]") if by == "s" else (m["t"], "time [s]")


def plot_channel(base, low, j: int, name: str, ax=None, by: str = "s"):
    """One channel of member ``j`` for both vehicles against distance (or time)."""
    ax = _ax(ax)
    label, scale = _DISPLAY.get(name, (name, 1.0))
    for res, color, who in ((base, BASE_COLOR, "base"), (low, LOW_WEAR_COLOR, "low-wear")):
        x, xl = _x(res, j, by)
        ax.plot(x, res.member(j, [name])[name] * scale, color=color, label=who)
    ax.set_xlabel(xl)
    ax.set_ylabel(label)
    ax.legend(fontsize=7)
    return ax


def plot_axle_channel(base, low, j: int, kind: str, ax=None, by: str = "s"):
    """Front (solid) and rear (dotted) ``kind`` in {'emission', 'torque', 'fy', 'fx'} for both vehicles."""
    ax = _ax(ax)
    label, scale = _DISPLAY[kind]
    prefix = {"emission": "emission_", "torque": "torque_", "fy": "fy_", "fx": "fx_"}[kind]
    for res, color, who in ((base, BASE_COLOR, "base"), (low, LOW_WEAR_COLOR, "low-wear")):
        x, xl = _x(res, j, by)
        m = res.member(j, [prefix + "f", prefix + "r"])
        ax.plot(x, m[prefix + "f"] * scale, "-", color=color, label=f"{who} front")
        ax.plot(x, m[prefix + "r"] * scale, ":", color=color, label=f"{who} rear")
    ax.set_xlabel(xl)
    ax.set_ylabel(label)
    ax.legend(fontsize=7, ncol=2)
    return ax


def scenario_figure(result, j: int):
    """The paper's panels for one run of a straight or curved scenario.

    Straight (Figs. 7-9): speed, acceleration, emission and torque.
    Curved (Figs. 10-12): lateral force, steering, emission and torque, plus
    the lateral offset of both vehicles.
    """
    from matplotlib.figure import Figure

    base, low = result.base, result.low_wear
    c, v = result.members[j]
    if result.scenario == "curved":
        fig = Figure(figsize=(12, 10))
        axs = fig.subplots(3, 2)
        plot_axle_channel(base, low, j, "fy", axs[0, 0])
        plot_channel(base, low, j, "steer", axs[0, 1])
        plot_axle_channel(base, low, j, "emission", axs[1, 0])
        plot_axle_channel(base, low, j, "torque", axs[1, 1])
        plot_channel(base, low, j, "n", axs[2, 0])
        plot_channel(base, low, j, "vx", axs[2, 1])
    else:
        fig = Figure(figsize=(12, 7))
        axs = fig.subplots(2, 2)
        plot_channel(base, low, j, "vx", axs[0, 0])
        plot_channel(base, low, j, "ax", axs[0, 1])
        plot_axle_channel(base, low, j, "emission", axs[1, 0])
        plot_axle_channel(base, low, j, "torque", axs[1, 1])
    fig.suptitle(f"{result.scenario}: condition eta = {c:g}, {v:g} km/h")
    fig.tight_layout()
    return fig


def braking_figure(result):
    """Speed and deceleration against distance for every braking run, and stopping distances vs the paper."""
    from matplotlib.figure import Figure

    base, low = result.base, result.low_wear
    fig = Figure(figsize=(15, 4))
    axs = fig.subplots(1, 3)
    for j, (c, v) in enumerate(result.members):
        ls = "-" if c == 1.0 else "--"
        for res, color in ((base, BASE_COLOR), (low, LOW_WEAR_COLOR)):
            m = res.member(j, ["s", "vx", "ax"])
            axs[0].plot(m["s"], m["vx"] * 3.6, ls, color=color, lw=1)
            axs[1].plot(m["s"], -m["ax"], ls, color=color, lw=1)
    axs[0].set_xlabel("distance [m]")
    axs[0].set_ylabel("speed [km/h]")
    axs[1].set_xlabel("distance [m]")
    axs[1].set_ylabel("deceleration [m/s²]")
    axs[0].set_title("orange base, blue low-wear; solid eta 1, dashed eta 0.5", fontsize=9)
    sim = [r["stopping_distance_m"] for r in result.rows]
    paper = [PAPER_TABLE3[(r["condition"], int(r["initial_speed_kmh"]))][0 if r["vehicle"] == "base" else 1]
             for r in result.rows]
    colors = [BASE_COLOR if r["vehicle"] == "base" else LOW_WEAR_COLOR for r in result.rows]
    axs[2].scatter(paper, sim, c=colors)
    lim = [0, max(max(sim), max(paper)) * 1.05]
    axs[2].plot(lim, lim, "k-", lw=0.8)
    axs[2].fill_between(lim, [0.95 * x for x in lim], [1.05 * x for x in lim], color="0.85", label="±5 %")
    axs[2].set_xscale("log")
    axs[2].set_yscale("log")
    axs[2].set_xlabel("Pham et al. 2025, Table 3 stopping distance [m]")
    axs[2].set_ylabel("simulated stopping distance [m]")
    axs[2].legend(fontsize=8)
    fig.tight_layout()
    return fig


_TRACE = [("t", "t [s]", 1.0), ("s", "s [m]", 1.0), ("n", "n [m]", 1.0), ("xi", "xi [rad]", 1.0),
          ("vx", "vx [m/s]", 1.0), ("vy", "vy [m/s]", 1.0), ("yaw_rate", "yaw_rate [rad/s]", 1.0),
          ("ax", "ax [m/s2]", 1.0), ("ay", "ay [m/s2]", 1.0), ("steer_driver", "steer_driver [rad]", 1.0),
          ("steer", "steer [rad]", 1.0), ("force_demand", "force_demand [N]", 1.0),
          ("force_ref_f", "force_ref_f [N]", 1.0), ("force_ref_r", "force_ref_r [N]", 1.0),
          ("fx_f", "fx_f [N]", 1.0), ("fx_r", "fx_r [N]", 1.0), ("fy_f", "fy_f [N]", 1.0),
          ("fy_r", "fy_r [N]", 1.0), ("slip_ratio_f", "slip_ratio_f [-]", 1.0),
          ("slip_ratio_r", "slip_ratio_r [-]", 1.0), ("torque_f", "torque_f [N*m]", 1.0),
          ("torque_r", "torque_r [N*m]", 1.0), ("emission_f", "emission_f [#/s]", 1.0),
          ("emission_r", "emission_r [#/s]", 1.0)]


def traces_frame(result, j: int, every_s: float = 0.05):
    """Both vehicles' traces of member ``j`` as one DataFrame (a ``vehicle`` column), every ``every_s`` s."""
    import pandas as pd

    frames = []
    for name, res in (("base", result.base), ("low_wear", result.low_wear)):
        dt = float(res.t[1] - res.t[0]) if res.t.size > 1 else every_s
        k = max(1, int(round(every_s / dt)))
        m = res.member(j, [c for c, _, _ in _TRACE if c != "t"])
        df = pd.DataFrame({h: m[c][::k] * f for c, h, f in _TRACE})
        df.insert(0, "vehicle", name)
        frames.append(df)
    return pd.concat(frames, ignore_index=True)


def ramp_figure(ramp):
    """A constant-radius ramp over lateral acceleration: steering, body slip, axle slip angles, wheel loads."""
    from matplotlib.figure import Figure

    s = ramp.states
    g = 9.80665
    ay = s["ay"] / g
    deg = 180.0 / np.pi
    fig = Figure(figsize=(12, 7))
    axs = fig.subplots(2, 2)
    axs[0, 0].plot(ay, s["steer"] * deg, color="k", label="steering angle")
    axs[0, 0].axhline(ramp.vehicle["wheelbase"] / ramp.radius * deg, color="0.6", ls=":", label="Ackermann L/R")
    axs[0, 0].set_ylabel("steering angle [deg]")
    axs[0, 0].set_title(f"understeer gradient {ramp.understeer_gradient_deg_per_g:.3f} deg/g; limit "
                        f"{ramp.lateral_limit_g:.3f} g", fontsize=9)
    axs[0, 1].plot(ay, s["beta"] * deg, color="k")
    axs[0, 1].set_ylabel("body slip angle [deg]")
    axs[1, 0].plot(ay, -s["slip_angle_f"] * deg, label="front axle")
    axs[1, 0].plot(ay, -s["slip_angle_r"] * deg, ":", label="rear axle")
    axs[1, 0].set_ylabel("|slip angle| [deg]")
    for k, ls in (("fl", "-"), ("fr", "-"), ("rl", ":"), ("rr", ":")):
        axs[1, 1].plot(ay, s[f"fz_{k}"] / 1e3, ls, label=k)
    axs[1, 1].set_ylabel("wheel load [kN]")
    for ax in axs.ravel():
        ax.set_xlabel("lateral acceleration [g]")
        if ax.get_legend_handles_labels()[0]:
            ax.legend(fontsize=7)
    fig.tight_layout()
    return fig


def step_steer_figure(res):
    """Step steer over time: steering angle, yaw rate and lateral acceleration with their steady values and
    the 10 % / 90 % levels, and the speed."""
    from matplotlib.figure import Figure

    tr = res.trace
    t = tr.t
    deg = 180.0 / np.pi
    g = 9.80665
    fig = Figure(figsize=(12, 7))
    axs = fig.subplots(2, 2)
    axs[0, 0].plot(t, tr.ch["steer"][:, 0] * deg, color="k")
    axs[0, 0].set_ylabel("road-wheel steering angle [deg]")
    for ax, key, scale, label, m in ((axs[0, 1], "r", deg, "yaw rate [deg/s]", res.yaw),
                                     (axs[1, 0], "ay", 1.0 / g, "lateral acceleration [g]", res.lat)):
        ax.plot(t, tr.ch[key][:, 0] * scale, color="tab:blue")
        ss = m["steady_state"] * scale
        ax.axhline(ss, color="0.4", ls="--", lw=1, label="steady state")
        for lv in (0.1, 0.9):
            ax.axhline(lv * ss, color="0.7", ls=":", lw=1)
        ax.axvline(res.t50, color="0.6", lw=1, label="50 % steer")
        ax.set_ylabel(label)
        ax.set_title(f"rise {m['rise_time_s']:.3f} s, response {m['response_time_s']:.3f} s, overshoot "
                     f"{m['overshoot_pct']:.1f} %", fontsize=9)
        ax.legend(fontsize=7)
    axs[1, 1].plot(t, tr.ch["vx"][:, 0] * 3.6, color="k")
    axs[1, 1].set_ylabel("speed [km/h]")
    for ax in axs.ravel():
        ax.set_xlabel("time [s]")
    fig.tight_layout()
    return fig


def braking_turn_figure(res):
    """Braking in a turn: the paths against the initial circle, speed, yaw-rate deviation and deceleration."""
    from matplotlib.figure import Figure

    tr = res.trace
    t = tr.t - res.t_brake
    deg = 180.0 / np.pi
    fig = Figure(figsize=(12, 8))
    axs = fig.subplots(2, 2)
    i0 = int(np.searchsorted(tr.t, res.t_brake - 1e-9))
    for j, d in enumerate(res.demands_g):
        lab = "full (ABS)" if d is None else f"{d:g} g demand"
        m = tr.active[:, j]
        m_after = m & (t >= 0)
        sp = np.hypot(tr.ch["vx"][:, j], tr.ch["vy"][:, j])
        axs[0, 0].plot(tr.ch["X"][m, j], tr.ch["Y"][m, j], label=lab)
        axs[0, 1].plot(t[m_after], sp[m_after] * 3.6, label=lab)
        ref = sp / res.radius0[j]
        axs[1, 0].plot(t[m_after], (tr.ch["r"][m_after, j] - ref[m_after]) * deg, label=lab)
        axs[1, 1].plot(t[m_after], -tr.ch["ax"][m_after, j], label=lab)
    c = res.centre[:, 0]
    phi = np.linspace(0, 2 * np.pi, 400)
    axs[0, 0].plot(c[0] + res.radius0[0] * np.cos(phi), c[1] + res.radius0[0] * np.sin(phi), color="0.6", ls=":",
                   lw=1, label="initial circle")
    axs[0, 0].plot(tr.ch["X"][i0, 0], tr.ch["Y"][i0, 0], "k.", label="brake onset")
    axs[0, 0].set_aspect("equal", adjustable="datalim")
    axs[0, 0].set_xlabel("X [m]")
    axs[0, 0].set_ylabel("Y [m]")
    axs[0, 1].set_ylabel("speed [km/h]")
    axs[1, 0].set_ylabel("yaw rate - v/R0 [deg/s] (+: turns in)")
    axs[1, 1].set_ylabel("deceleration [m/s²]")
    for ax in axs.ravel()[1:]:
        ax.set_xlabel("time after brake onset [s]")
    for ax in axs.ravel():
        ax.legend(fontsize=7)
    fig.tight_layout()
    return fig
