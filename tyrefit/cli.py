"""The ``tyrefit`` command line.

Every subcommand and flag here is a contract (``shared/DESIGN.md``): scripts
outside the package call them.  This module only parses arguments and
dispatches to ``tyrefit.commands.<module>.run(args) -> int``; the work lives
in the library.

Exit codes: 0 success, 2 bad input (one line on stderr, no traceback unless
``--debug``), 1 an unexpected internal error.
"""

from __future__ import annotations

import os
import signal
import sys


def _startup_interrupt(signum, frame):  # pragma: no cover - exercised in a subprocess
    """Ctrl-C before a command has started: nothing is written yet, so one line and exit 130."""
    try:
        os.write(2, b"tyrefit: interrupted\n")
    finally:
        os._exit(130)


#: installed first thing when ``tyrefit`` is the program (not when a script or test imports the module)
if __name__ == "__main__" or os.path.basename(sys.argv[0] if sys.argv else "").removesuffix(".exe") == "tyrefit":
    try:
        signal.signal(signal.SIGINT, _startup_interrupt)
    except (ValueError, OSError):  # pragma: no cover - not the main thread
        pass

import argparse
import importlib
import math
from collections.abc import Sequence

from ._version import __version__
from .errors import OutputError, TyrefitError, ValueRangeError, cli_style
from .io.inputs import DEFAULT_MAX_MB, check_input, set_max_size_mb
from .io.outputs import check_output, check_report_dir, current_run, os_error_message, output_run

__all__ = ["main", "build_parser", "run_checked"]


class _Parser(argparse.ArgumentParser):
    """argparse that reports usage errors as one line and exit code 2."""

    def error(self, message: str) -> None:  # noqa: D401
        self.exit(2, f"{self.prog}: error: {message}\n")


#: numeric flags of every command: attribute -> (low, high, low excluded, what is accepted).  Checked
#: after parsing (finite, in range), so a bad value is one line and exit code 2 like any bad input.
NUMERIC_FLAGS: dict[str, tuple[float | None, float | None, bool, str]] = {
    "rated_load": (0.0, 200e3, True, "the rated load must be a positive, finite force in N, at most 200 kN (e.g. 6031)"),
    "road_mu": (0.05, 1.5, False, "the road adhesion coefficient must be between 0.05 and 1.5"),
    "camber": (-10.0, 10.0, False, "the brush model's camber range is -10 to 10 deg"),
    "seed": (0, 2**32 - 1, False, "the seed must be an integer from 0 to 2**32 - 1"),
    "workers": (1, 1024, False, "need at least 1 worker process (at most 1024)"),
    "max_size": (0.0, 1e6, True, "the input size limit must be a positive number of MB"),
}


def validate_numbers(args: argparse.Namespace) -> None:
    """Refuse NaN, inf and out-of-range values of :data:`NUMERIC_FLAGS` (one-line ValueRangeError)."""
    for name, (lo, hi, lo_open, text) in NUMERIC_FLAGS.items():
        v = getattr(args, name, None)
        if v is None or isinstance(v, bool) or not isinstance(v, (int, float)):
            continue
        bad = not math.isfinite(v) or (lo is not None and (v <= lo if lo_open else v < lo)) \
            or (hi is not None and v > hi)
        if bad:
            raise ValueRangeError(f"--{name.replace('_', '-')} {v:g}: {text}")


def _common() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(add_help=False)
    p.add_argument("--force", action="store_true", help="replace existing outputs")
    p.add_argument("--debug", action="store_true", help="show tracebacks on errors")
    p.add_argument("--max-size", type=float, default=None, metavar="MB",
                   help=f"largest input file read, in MB (default {DEFAULT_MAX_MB:g})")
    return p


def _convention(p: argparse.ArgumentParser) -> None:
    p.add_argument("--convention", choices=("iso", "sae"), default="iso",
                   help="sign convention of the data file (sae: FSAE TTC, FZ negative); default iso")


def _allow_unphysical(p: argparse.ArgumentParser) -> None:
    p.add_argument("--allow-unphysical", action="store_true",
                   help="evaluate a tyre file even if its model is unphysical over its declared range")


def _allow_mirrored(p: argparse.ArgumentParser) -> None:
    p.add_argument("--allow-mirrored", action="store_true",
                   help="fit (inspect: do not list as a problem) data whose camber thrust, pneumatic trail or Fx "
                        "has the sign of a mirrored tyre")


def add_scenario_parsers(ssub, common, allow_unphysical) -> None:
    """The ``sim braking|straight|curved|ramp|step_steer|braking_turn`` subparsers."""
    for name, text in (("braking", "emergency braking, 30/60/120 km/h, conditions 0.5 and 1.0"),
                       ("straight", "accelerate to speed then brake on a straight path"),
                       ("curved", "straight, arc at half the UK desirable minimum radius, straight"),
                       ("ramp", "steady-state constant-radius ramp to the limit: understeer gradient, lateral "
                                "limit"),
                       ("step_steer", "step steer from straight running (ISO 7401 style): yaw-rate and lateral-"
                                      "acceleration rise time, overshoot, steady-state gain"),
                       ("braking_turn", "braking in a turn (ISO 7975 style): deceleration, yaw-rate and path "
                                        "deviation, stopping distance")):
        s = ssub.add_parser(name, parents=[common], help=text)
        s.add_argument("--front", metavar="F.tir", help="front (hard, low-wear) tyre; default the bundled one")
        s.add_argument("--rear", metavar="R.tir", help="rear (soft) tyre; default the bundled one")
        s.add_argument("--vehicle", metavar="FILE|PRESET", default="ev",
                       help="vehicle file (TOML or JSON) or preset: ev (default, the car of Pham et al. 2025), "
                            "fsae, light_truck")
        s.add_argument("--strict", action="store_true",
                       help="refuse when a tyre works outside the load/slip envelope its file declares")
        s.add_argument("--road-friction", type=float, default=1.0, metavar="FACTOR",
                       help="the road's friction as a factor on the tyres' test surface (default 1; belt-rig data "
                            "such as FSAE TTC's typically need 0.6-0.7 for a dry track): peak forces scale, "
                            "slip stiffnesses do not")
        if name == "step_steer":
            s.add_argument("--speed", type=float, default=None, metavar="KMH", help="speed [km/h] (default 80)")
            s.add_argument("--ay", type=float, default=None, metavar="G",
                           help="steady-state lateral acceleration the step aims at [g] (default 0.4)")
        if name == "braking_turn":
            s.add_argument("--radius", type=float, default=None, metavar="M",
                           help="radius of the steady cornering before braking [m] (default 100)")
            s.add_argument("--ay", type=float, default=None, metavar="G",
                           help="lateral acceleration of the steady cornering [g] (default 0.5)")
        s.add_argument("--json", metavar="OUT.json")
        s.add_argument("--report", metavar="DIR")
        allow_unphysical(s)


def build_parser() -> argparse.ArgumentParser:
    common = _common()
    parser = _Parser(prog="tyrefit", description="Tyre rig data to Pacejka '89 tyre models.")
    parser.add_argument("--version", action="version", version=_version())
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=_Parser)
    sub.required = True

    p = sub.add_parser("fit", parents=[common],
                       help="fit a PAC89 (or, with --model, Magic Formula 6.1/5.2) tyre to rig data")
    p.add_argument("data", metavar="DATA", nargs="+",
                   help="data file(s) of one tyre; several (cornering + drive/brake) need --model mf61 or mf52")
    p.add_argument("--model", choices=("pac89", "mf52", "mf61"), default="pac89",
                   help="tyre model family and .tir layout written (default pac89)")
    p.add_argument("--patch", metavar="PATCH.csv", help="contact-patch data (needed for static-rig tests, Eq. 1)")
    p.add_argument("--rig", metavar="RIG.json", help="displacement-to-slip calibration from 'tyrefit rig calibrate'")
    p.add_argument("--vertical", metavar="VERTICAL.csv", help="vertical-stiffness test (VERTICAL_STIFFNESS in the .tir)")
    p.add_argument("--effects", metavar="E1,E2", help="fit the diagnose start model plus these effects")
    p.add_argument("--by", choices=("pressure", "camber", "speed"),
                   help="one tyre per level of this condition (TYRE_<level>.tir) and a summary table")
    p.add_argument("--rated-load", type=float, metavar="NEWTONS",
                   help="rated load [N]: FNOMIN of the tyre, the 'overload' effect, stiffness estimates")
    p.add_argument("--size", metavar="SIZE", help="tyre size, e.g. 385/65R22.5 or 205/55R16: unloaded radius, width, "
                                                  "aspect ratio, and estimates of mass, inertia and damping")
    p.add_argument("--cost", choices=("l1", "l2", "soft_l1", "huber"), default="l2",
                   help="l1: sum of absolute errors (Komana et al. Eq. 5); l2: ordinary least squares (default); "
                        "huber, soft_l1: outlier-resistant, on mu scaled by each sweep's noise")
    p.add_argument("--static-part", choices=("peak", "sliding"), default="peak",
                   help="static tests: which part of the static curve feeds the rolling-tyre fit")
    p.add_argument("--out", required=True, metavar="TYRE.tir")
    p.add_argument("--json", metavar="CHRONO.json", help="also write Chrono's PAC89 JSON")
    p.add_argument("--report", metavar="DIR")
    _convention(p)
    _allow_mirrored(p)

    p = sub.add_parser("eval", parents=[common], help="a tyre file's forces at the points of a CSV (any family)")
    p.add_argument("tyre", metavar="TYRE")
    p.add_argument("--points", required=True, metavar="POINTS.csv",
                   help="fz, slip_angle and optional slip_ratio, camber, pressure, speed with unit headers")
    p.add_argument("--out", required=True, metavar="FORCES.csv")
    _allow_unphysical(p)

    p = sub.add_parser("rig", help="static-rig calibration")
    rsub = p.add_subparsers(dest="rig_command", metavar="RIG_COMMAND", parser_class=_Parser)
    rsub.required = True
    c = rsub.add_parser("calibrate", parents=[common], help="fit Eq. 1's f(dy/L) on a tyre tested on both rigs")
    c.add_argument("--static", required=True, metavar="STTR.csv")
    c.add_argument("--dynamic", required=True, metavar="DTTR.csv")
    c.add_argument("--patch", required=True, metavar="PATCH.csv")
    c.add_argument("--out", required=True, metavar="RIG.json")
    c.add_argument("--report", metavar="DIR")

    p = sub.add_parser("compare", parents=[common], help="compare two tyre files (and data)")
    p.add_argument("tyre_a", metavar="A.tir")
    p.add_argument("tyre_b", metavar="B.tir")
    p.add_argument("--data", metavar="DATA")
    p.add_argument("--report", metavar="DIR")
    p.add_argument("--json", metavar="OUT.json")
    _convention(p)
    _allow_unphysical(p)

    p = sub.add_parser("diagnose", parents=[common], help="find the physical effects the model is missing")
    p.add_argument("data", metavar="DATA", nargs="+",
                   help="one record, or several of one tyre (cornering and drive/brake): Fy, Mz and Fx are diagnosed")
    p.add_argument("--start", metavar="E1,E2", help="effects in the start model (besides base PAC89)")
    p.add_argument("--rated-load", type=float, metavar="NEWTONS", help="rated load for the 'overload' effect [N]")
    p.add_argument("--json", required=True, metavar="OUT.json")
    p.add_argument("--report", metavar="DIR")
    p.add_argument("--seed", type=int, default=0, help="random seed for resampling")
    p.add_argument("--patch", metavar="PATCH.csv", help="contact-patch data (static-rig tests, Eq. 1; as for fit)")
    p.add_argument("--rig", metavar="RIG.json", help="displacement-to-slip calibration from 'tyrefit rig calibrate'")
    p.add_argument("--static-part", choices=("peak", "sliding"), default="peak",
                   help="static tests: which part of each push is diagnosed (as for fit)")
    p.add_argument("--base", choices=("pac89", "mf61", "mf52"), default="pac89",
                   help="the model to diagnose: PAC89 grown effect by effect (default), or the Magic Formula tyre "
                        "`fit --model mf61|mf52` writes, and what it still misses")
    _convention(p)

    p = sub.add_parser("sim", help="vehicle simulations (scenarios of Pham et al. 2025, road adhesion of "
                                   "Zhang et al. 2024)")
    ssub = p.add_subparsers(dest="scenario", metavar="SCENARIO", parser_class=_Parser)
    ssub.required = True
    add_scenario_parsers(ssub, common, _allow_unphysical)
    s = ssub.add_parser("adhesion", parents=[common], help="EKF road-adhesion estimation (Zhang et al. 2024)")
    s.add_argument("--road-mu", type=float, default=0.8, metavar="MU")
    s.add_argument("--camber", type=float, default=0.0, metavar="DEG")
    s.add_argument("--json", metavar="OUT.json")
    s.add_argument("--report", metavar="DIR")

    p = sub.add_parser("slip", parents=[common], help="longitudinal slip characteristics (Ghasemi et al. 2021)")
    p.add_argument("data", metavar="DATA")
    p.add_argument("--json", metavar="OUT.json")
    p.add_argument("--report", metavar="DIR")
    _convention(p)

    p = sub.add_parser("traction", parents=[common],
                       help="treadwear-traction law from braking tests (Pham et al. 2025)")
    p.add_argument("data", metavar="BRAKING.csv")
    p.add_argument("--json", metavar="OUT.json")
    p.add_argument("--report", metavar="DIR")

    p = sub.add_parser("batch", help="batch operations on tyre databases")
    bsub = p.add_subparsers(dest="batch_command", metavar="BATCH_COMMAND", parser_class=_Parser)
    bsub.required = True
    b = bsub.add_parser("fit", parents=[common], help="fit every data file in a folder or glob")
    b.add_argument("source", metavar="DIR_OR_GLOB")
    b.add_argument("--out", required=True, metavar="DIR")
    sched = b.add_mutually_exclusive_group()
    sched.add_argument("--scheduler", metavar="ADDRESS", help="Dask scheduler address (tcp://host:8786, tls://...)")
    sched.add_argument("--scheduler-file", metavar="FILE",
                       help="Dask scheduler file (written by 'dask scheduler --scheduler-file FILE')")
    b.add_argument("--workers", type=int, metavar="N", help="local worker processes (default: CPU count)")
    b.add_argument("--cost", choices=("l1", "l2", "soft_l1", "huber"), default="l2")
    b.add_argument("--model", choices=("pac89", "mf52", "mf61"), default="pac89",
                   help="tyre model family of every tyre written (default pac89)")
    b.add_argument("--manifest", metavar="TYRES.csv",
                   help="per-file design data: columns file, size, rated_load [N] (as fit --size --rated-load)")
    _convention(b)
    _allow_mirrored(b)

    p = sub.add_parser("inspect", parents=[common], help="say what a data or tyre file holds")
    p.add_argument("file", metavar="FILE")
    p.add_argument("--json", metavar="OUT.json")
    _convention(p)
    _allow_mirrored(p)

    p = sub.add_parser("demo", parents=[common], help="run the main job on the bundled data")
    p.add_argument("--out", default="reports/demo", metavar="DIR")
    return parser


#: subcommand -> module in tyrefit.commands that holds ``run(args) -> int``
COMMANDS = {
    "fit": "fit",
    "rig": "rig",
    "compare": "compare",
    "eval": "eval",
    "diagnose": "diagnose",
    "sim": "sim",
    "slip": "slip",
    "traction": "traction",
    "batch": "batch",
    "inspect": "inspect",
    "demo": "demo",
}


#: (command, subcommand) pairs served by a module of their own
SUBCOMMANDS = {("sim", "adhesion"): "adhesion"}


def _module_for(args: argparse.Namespace) -> str:
    sub = getattr(args, "scenario", None)
    return SUBCOMMANDS.get((args.command, sub), COMMANDS[args.command])


def _version() -> str:
    return f"tyrefit {__version__}"


#: argument attributes that name input files (any command; lists allowed)
INPUT_ATTRS = ("data", "patch", "rig", "vertical", "tyre_a", "tyre_b", "front", "rear", "file", "static",
               "dynamic", "tyre", "points", "source")
#: commands whose ``--out`` is a folder: (command, subcommand) -> True when it is a report-like folder
_OUT_FOLDERS = {"demo": True, "batch": False}


def _paths(v) -> list[str]:
    if v is None:
        return []
    return [str(x) for x in v] if isinstance(v, (list, tuple)) else [str(v)]


def _io_plan(args: argparse.Namespace) -> tuple[list[str], list[str], list[str]]:
    """(input files, output files, report folders) named by the arguments."""
    inputs: list[str] = []
    for name in INPUT_ATTRS:
        for v in _paths(getattr(args, name, None)):
            if name == "source":  # batch: a folder, a glob or a file; the batch checks each file it finds
                if os.path.exists(v):
                    check_input(v, "a data file", folder_ok=True)
                continue
            check_input(v, "a data or tyre file")
            inputs.append(v)
    files, folders = [], []
    out_folder = _OUT_FOLDERS.get(args.command)
    for name in ("out", "json"):
        for v in _paths(getattr(args, name, None)):
            if name == "out" and out_folder is not None:
                if out_folder:
                    folders.append(v)
            else:
                files.append(v)
    folders += _paths(getattr(args, "report", None))
    return inputs, files, folders


def _preflight(args: argparse.Namespace, inputs, files, folders) -> None:
    """Refuse bad outputs before any work: inputs as outputs, duplicates, folders, existing files."""
    run = current_run()
    force = bool(getattr(args, "force", False))
    seen: dict[str, str] = {}
    for v in files + folders:
        r = os.path.realpath(v)
        if r in seen:
            raise OutputError(f"{v}: named twice as an output (also {seen[r]}); give each output its own name")
        seen[r] = v
    for v in files:
        check_output(v, force)
        parent = os.path.dirname(os.path.abspath(v))
        if os.path.isdir(parent) and not os.access(parent, os.W_OK):
            raise OutputError(f"{v}: cannot write in {parent} (read-only or permission denied)")
    for v in folders:
        run.check_not_input(v)
        check_report_dir(v, force)
        for r in (os.path.realpath(i) for i in inputs):
            if os.path.realpath(v) == r:
                raise OutputError(f"{v}: is an input of this run; choose another output folder")
    if args.command == "batch":
        out = getattr(args, "out", None)
        if out and os.path.exists(out) and not os.path.isdir(out):
            raise OutputError(f"{out}: exists and is not a folder; --out needs a folder for the .tir files")


def _run(args: argparse.Namespace) -> int:
    validate_numbers(args)
    set_max_size_mb(getattr(args, "max_size", None))
    inputs, files, folders = _io_plan(args)
    module = importlib.import_module(f"tyrefit.commands.{_module_for(args)}")
    for m in ("numpy", "pandas"):  # the libraries every command imports, still under the start-up handler
        importlib.import_module(m)
    _set_sigint(_run_interrupt)  # from here a Ctrl-C unwinds: staged outputs are removed, exit 130
    if args.command == "batch":  # a batch commits each tyre as it finishes (tyrefit.workflows.batch)
        with output_run(inputs, folders, force=getattr(args, "force", False)):
            _preflight(args, inputs, files, folders)
        return int(module.run(args) or 0)
    code = 0
    with output_run(inputs, folders, force=getattr(args, "force", False)):
        _preflight(args, inputs, files, folders)
        code = int(module.run(args) or 0)
        if code not in (0, 1):  # a command that reports failure by its exit code writes nothing
            raise _Abort(code)
    return code


class _Abort(Exception):
    def __init__(self, code: int):
        super().__init__(code)
        self.code = code


class _PipeSafeStdout:
    """``sys.stdout`` that survives a reader closing the pipe (``tyrefit fit ... | head -1``).

    A command prints while its outputs are still staged (:func:`tyrefit.io.outputs.output_run`
    commits them when the command returns), so a ``BrokenPipeError`` from a print used to abort
    the run and leave nothing on disk.  Here the first broken write points file descriptor 1 at
    ``os.devnull`` (the recipe of Python's ``signal`` documentation, "Note on SIGPIPE") and
    drops the rest of the text: the command finishes, its files are committed, the exit code
    is the command's.
    """

    def __init__(self, stream):
        self._stream = stream
        self.broken = False

    def write(self, text):
        if not self.broken:
            try:
                return self._stream.write(text)
            except BrokenPipeError:
                self._break()
        return len(text)

    def flush(self):
        if not self.broken:
            try:
                self._stream.flush()
            except BrokenPipeError:
                self._break()

    def _break(self) -> None:
        self.broken = True
        try:
            devnull = os.open(os.devnull, os.O_WRONLY)
            os.dup2(devnull, self._stream.fileno())
            os.close(devnull)
        except (OSError, ValueError, AttributeError):  # no real file descriptor (a test's capture)
            pass

    def __getattr__(self, name):
        return getattr(self._stream, name)


def _set_sigint(handler):
    """Install a SIGINT handler (main thread only); return the previous one, or None."""
    try:
        return signal.signal(signal.SIGINT, handler)
    except (ValueError, OSError):  # not the main thread
        return None


#: where a KeyboardInterrupt cannot propagate and is printed as "Exception ignored in ...": weakref
#: callbacks and finalizers (importlib's module-lock callback, __del__)
_FRAGILE_NAMES = ("__del__", "cb", "_remove", "_callback")


def _run_interrupt(signum, frame):
    """Ctrl-C while a command runs: KeyboardInterrupt, except inside a finalizer or importlib's
    bootstrap, where it would be printed and dropped; there it is delivered again 20 ms later."""
    f = frame
    if f is not None and (f.f_code.co_filename.startswith("<frozen importlib") or f.f_code.co_name in _FRAGILE_NAMES):
        import threading

        t = threading.Timer(0.02, os.kill, (os.getpid(), signal.SIGINT))
        t.daemon = True
        t.start()
        return
    raise KeyboardInterrupt


def main(argv: Sequence[str] | None = None) -> int:
    """Run the command line; return the exit code."""
    previous = _set_sigint(_startup_interrupt) if _is_program() else None
    try:
        parser = build_parser()
        args = parser.parse_args(argv)
        outer = sys.stdout
        if not isinstance(outer, _PipeSafeStdout):
            sys.stdout = _PipeSafeStdout(outer)
        try:
            with cli_style():  # messages name options as flags (--rated-load), not keywords
                return _main(args)
        finally:
            if sys.stdout is not outer:
                sys.stdout.flush()
                sys.stdout = outer
    finally:
        if previous is not None:
            _set_sigint(previous)


def _is_program() -> bool:
    """Is this process the ``tyrefit`` program (entry point or ``python -m tyrefit.cli``)?"""
    return signal.getsignal(signal.SIGINT) is _startup_interrupt


def _main(args: argparse.Namespace) -> int:
    debug = getattr(args, "debug", False)
    try:
        return _run(args)
    except _Abort as exc:
        return exc.code
    except TyrefitError as exc:
        if debug:
            raise
        msg = " ".join(str(exc).split())  # one line
        print(f"tyrefit {args.command}: error: {msg}", file=sys.stderr)
        return 2
    except OSError as exc:  # an output or input the operating system refused
        if debug:
            raise

        what = "cannot read or write"
        print(f"tyrefit {args.command}: error: {' '.join(os_error_message(exc, None, what).split())}",
              file=sys.stderr)
        return 2
    except MemoryError:
        if debug:
            raise
        print(f"tyrefit {args.command}: error: out of memory; the input is too large for this machine "
              "(see --max-size)", file=sys.stderr)
        return 2
    except KeyboardInterrupt:  # pragma: no cover - exercised in a subprocess
        _set_sigint(signal.SIG_IGN)  # a second Ctrl-C while saying so is not a traceback
        print("tyrefit: interrupted", file=sys.stderr)
        return 130


def run_checked(argv: Sequence[str]) -> None:
    """Run ``tyrefit ARGV`` and raise :class:`RuntimeError` unless it exits 0 (for pipelines)."""
    code = main(list(argv))
    if code != 0:
        raise RuntimeError(f"tyrefit {' '.join(list(argv)[:2])} exited {code}")


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
