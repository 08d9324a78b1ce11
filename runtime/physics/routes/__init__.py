"""The linear stability of the top hovering on the axis, by its two routes (thesis 3.3.9-3.3.16):
route "discriminant" (ray_algebra: the ray polynomial in exact rational arithmetic, with brent, the
scalar root finder it and the resonances use) and route "eigenvalues" (eigen_route: the generated
Jacobian's spectrum on the imaginary axis); the result both give and compare (result), and where the
level top's modes meet (mode_crossings), which the tilted base's analysis probes. No sympy here."""
