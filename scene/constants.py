"""Physical constants, defined once for derive/ and runtime/ (pure Python)."""

MU0 = 1.25663706212e-6  # vacuum permeability, N/A^2 (CODATA 2018)
