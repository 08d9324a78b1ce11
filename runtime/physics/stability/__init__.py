"""The linear stability of the top over every apparatus, and what it answers: the analysis (analysis:
`stability_of`, the on-axis routes, or the tilted base's or the tilted magnet's), its truncation check
off the axis (off_axis_truncation), the linear modes on the axis, over a tilted base and in the frame
turning with a tilted magnet (modes, tilted_modes, rotating_modes) and the resonances among them
(resonances), the `stability` command's answer `Stability` (answer) with its words (view), and the
same quantities as differentiable CasADi Functions for the designs (differentiable). The top room."""
