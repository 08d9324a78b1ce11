"""The `levitron` subcommands, one module each (protocol in docs/INTERFACES.md)."""

COMMANDS = (
    "derive",
    "info",
    "field",
    "equilibrium",
    "stability",
    "optimize",
    "figures",
    "simulate",
    "bench",
    "scan",
    "launch",
    "trim",
    "compare",
    "report",
)
