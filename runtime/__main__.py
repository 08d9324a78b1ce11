"""`python -m runtime ...`: the `levitron` command (runtime/cli/main.py)."""
import sys

from runtime.cli.main import main

sys.exit(main())
