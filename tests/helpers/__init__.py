"""Code only the tests use: derivations kept as independent routes (stability_derivation.py)."""
