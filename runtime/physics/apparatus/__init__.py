"""What a real apparatus adds to the thesis's ideal top, each answered off the axis: a tilted base
(tilted_equilibrium, tilted_stability and its plot tilt_plot; level_only names what serves a level
base only), a magnet tilted off the top's axis (its periodic orbit periodic_orbit, the Floquet
multipliers by shooting in multipliers, the fast route rotating_equilibrium, the spin window and the
moment tolerance in moment_tilt), and air (friction: a flight's time and the spin at which it falls)."""
