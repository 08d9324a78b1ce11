"""`python -m levitron ...`: the `levitron` command (runtime/cli/main.py)."""
import sys

from levitron.runtime.cli.main import main

sys.exit(main())
