"""The `levitron` subcommands, one module each (protocol in docs/INTERFACES.md)."""

COMMANDS = (
    "scenes",
    "keys",
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
    "schema",
)
