"""Helpers shared by the fuzz tests (tests/test_fuzz_*.py): mutation strategies and the oracle.

The oracle: a reader given any bytes either returns or raises a
:class:`tyrefit.errors.TyrefitError`; any other exception is a bug.
"""

from __future__ import annotations

import tempfile

import numpy as np
from pathlib import Path

from hypothesis import HealthCheck, settings
from hypothesis import strategies as st

from tyrefit.errors import TyrefitError

#: examples per fuzz test: the loaded hypothesis profile's budget (tests/conftest.py: 'ci' 200,
#: 'long' 5000), halved for the slower file readers
EXAMPLES = settings().max_examples
FUZZ = settings(max_examples=EXAMPLES, deadline=None, suppress_health_check=[HealthCheck.too_slow])
FUZZ_HALF = settings(max_examples=max(EXAMPLES // 2, 10), deadline=None,
                     suppress_health_check=[HealthCheck.too_slow])
#: structured properties of whole files (each example reads a file of sweeps): a twentieth
FUZZ_FEW = settings(max_examples=max(EXAMPLES // 20, 8), deadline=None,
                    suppress_health_check=[HealthCheck.too_slow])

_DIR = Path(tempfile.mkdtemp(prefix="tyrefit-fuzz-"))

#: tokens that break parsers: empty, special floats, overflow, quotes, brackets, keywords, separators
NASTY = ["", " ", "nan", "NaN", "inf", "-inf", "1e309", "-1e309", "1e-330", "-0", "0", "1e5", "abc", "NOTAVAIL",
         "[", "]", "[N]", "[kN]", "[furlong]", "{", "}", "{a b}", '"', "'", "''", "**", "**MEASURDATA",
         "**MEASURCHANNELS", "$", "!", "=", "==", "#", ",", ";", "\t", "\n", "\r\n", "\r", "\x00", "\xff", "é",
         "1,5", "9" * 400, "9" * 5000, "1d5", "0x1F", "--", "PROPERTY_FILE_FORMAT = 'PAC89'", "[MODEL]",
         "[LATERAL_COEFFICIENTS]", "a0 = ", "true", "null", "[]", "{}", "-1", "1e400", "1_000"]


def write(name: str, data: bytes) -> Path:
    """Write ``data`` to a scratch file called ``name`` (one per test, overwritten) and return it."""
    p = _DIR / name
    p.write_bytes(data)
    return p


def only_tyrefit_errors(reader, path) -> None:
    """Call ``reader(path)``; let only TyrefitError through (and swallow it)."""
    try:
        reader(path)
    except TyrefitError:
        pass


_index = st.integers(min_value=0, max_value=1 << 20)
_token = st.one_of(st.sampled_from(NASTY), st.text(max_size=12), st.floats().map(repr))
_op = st.one_of(
    st.tuples(st.just("delete"), _index, st.integers(1, 64)),
    st.tuples(st.just("insert"), _index, st.binary(min_size=1, max_size=16)),
    st.tuples(st.just("insert_token"), _index, _token),
    st.tuples(st.just("byte"), _index, st.integers(0, 255)),
    st.tuples(st.just("drop_line"), _index),
    st.tuples(st.just("dup_line"), _index),
    st.tuples(st.just("swap_lines"), _index, _index),
    st.tuples(st.just("replace_field"), _index, _token),
    st.tuples(st.just("truncate"), _index),
)


def _apply(data: bytes, op: tuple) -> bytes:
    kind = op[0]
    n = len(data)
    if kind == "delete":
        i = op[1] % (n + 1)
        return data[:i] + data[i + op[2]:]
    if kind == "insert":
        i = op[1] % (n + 1)
        return data[:i] + op[2] + data[i:]
    if kind == "insert_token":
        i = op[1] % (n + 1)
        return data[:i] + op[2].encode("utf-8", "surrogatepass") + data[i:]
    if kind == "byte":
        if not n:
            return data
        i = op[1] % n
        return data[:i] + bytes([op[2]]) + data[i + 1:]
    if kind == "truncate":
        return data[:op[1] % (n + 1)]
    lines = data.split(b"\n")
    k = op[1] % len(lines)
    if kind == "drop_line":
        del lines[k]
    elif kind == "dup_line":
        lines.insert(k, lines[k])
    elif kind == "swap_lines":
        j = op[2] % len(lines)
        lines[k], lines[j] = lines[j], lines[k]
    elif kind == "replace_field":
        import re

        parts = re.split(rb"([,;\t= ]+)", lines[k])
        fields = list(range(0, len(parts), 2))
        f = fields[op[1] % len(fields)]
        parts[f] = op[2].encode("utf-8", "surrogatepass")
        lines[k] = b"".join(parts)
    return b"\n".join(lines)


def mutated(valid: bytes, max_ops: int = 6):
    """Strategy: ``valid`` with 1..max_ops random edits (byte, token, field and line level)."""
    return st.lists(_op, min_size=1, max_size=max_ops).map(lambda ops: _mutate(valid, ops))


def _mutate(data: bytes, ops) -> bytes:
    for op in ops:
        data = _apply(data, op)
    return data


# --------------------------------------------------------------------------- issue 15: plausibility profiles

#: whitespace runs that used to make header parsing backtrack (minutes for 5000 spaces)
WHITESPACE = st.lists(st.sampled_from([" ", "\t", "\u00a0", "  "]), min_size=0, max_size=40).map("".join) | \
    st.integers(1000, 20000).map(lambda n: " " * n)


def sweep_table(loads=(2000.0, 4000.0, 6000.0), n=21, seed=0) -> np.ndarray:
    """Rows (run, slip_angle [deg], fy [N], fz [N]) of ISO-W slip-angle sweeps (peak mu about 1)."""
    rng = np.random.default_rng(seed)
    rows = []
    for r, fz in enumerate(loads):
        a = np.linspace(-10, 10, n)
        fy = -fz * np.sin(1.4 * np.arctan(0.3 * a)) + 0.01 * fz * rng.standard_normal(n)
        rows += [(r, a[i], fy[i], fz) for i in range(n)]
    return np.array(rows)


def table_csv(arr: np.ndarray, header: str = "run,slip_angle [deg],fy [N],fz [N]") -> bytes:
    lines = [header] + [f"{int(r)},{a:.5g},{f:.6g},{z:.6g}" for r, a, f, z in arr]
    return ("\n".join(lines) + "\n").encode()
