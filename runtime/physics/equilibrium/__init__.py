"""Where the top hovers on the axis (thesis 3.3.1-3.3.3): the one equilibrium finder (finder:
hover_height, equilibria_of), its root search (root_survey), what it finds (report: each vertical
equilibrium, the singular stretches, z_c and the largest mass), the stable and adiabatic bands
(bands), and the `equilibrium` command's answer, `Equilibria` (answer), with its words (view)."""
