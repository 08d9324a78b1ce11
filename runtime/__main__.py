"""`python -m runtime ...`: the `levitron` command (runtime/cli.py)."""
import sys

from .cli import main

sys.exit(main())
