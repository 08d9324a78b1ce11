"""`python -m runtime.cli ...`: the `levitron` command."""
import sys

from runtime.cli.main import main

sys.exit(main())
