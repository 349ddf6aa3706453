"""Run small dense linear algebra on one BLAS thread.

The fit's Jacobians are tall and thin (n points x <= 18 coefficients).  For
such matrices a multi-threaded OpenBLAS spends more time synchronising its
threads than computing, and on a shared, loaded machine an SVD of a
2000 x 14 matrix was measured 50x slower with two threads than with one.
:func:`single_threaded_blas` sets the OpenBLAS libraries that numpy and
scipy ship to one thread for the duration of a fit and restores the previous
setting afterwards (what ``threadpoolctl`` does, without the dependency).
If the libraries are not found it does nothing.
"""

from __future__ import annotations

import contextlib
import ctypes
import glob
import os
import threading

_LOCK = threading.Lock()
_DEPTH = 0
_SAVED: list[tuple[object, int]] = []
_LIBS: list[tuple[object, object]] | None = None


def _libs() -> list[tuple[object, object]]:
    global _LIBS
    if _LIBS is not None:
        return _LIBS
    found = []
    try:
        import numpy
        import scipy

        for pkg in (numpy, scipy):
            for f in glob.glob(os.path.dirname(pkg.__file__) + ".libs/*openblas*.so*"):
                lib = ctypes.CDLL(f)
                for sym in ("scipy_openblas_set_num_threads64_", "scipy_openblas_set_num_threads",
                            "openblas_set_num_threads64_", "openblas_set_num_threads"):
                    get = sym.replace("_set_", "_get_")
                    if hasattr(lib, sym) and hasattr(lib, get):
                        found.append((getattr(lib, sym), getattr(lib, get)))
                        break
    except Exception:  # pragma: no cover - platform without these libraries
        found = []
    _LIBS = found
    return found


@contextlib.contextmanager
def single_threaded_blas():
    """Context manager: OpenBLAS on one thread inside, previous setting restored after."""
    global _DEPTH
    with _LOCK:
        if _DEPTH == 0:
            _SAVED.clear()
            for setter, getter in _libs():
                try:
                    _SAVED.append((setter, int(getter())))
                    setter(1)
                except Exception:  # pragma: no cover
                    pass
        _DEPTH += 1
    try:
        yield
    finally:
        with _LOCK:
            _DEPTH -= 1
            if _DEPTH == 0:
                for setter, n in _SAVED:
                    try:
                        setter(n)
                    except Exception:  # pragma: no cover
                        pass
