"""Pure, vectorised tyre models: numpy in, numpy out, SI units, no checks."""
