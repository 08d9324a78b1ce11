"""`python -m levitron.runtime.cli ...`: the `levitron` command."""
import sys

from levitron.runtime.cli.main import main

sys.exit(main())
