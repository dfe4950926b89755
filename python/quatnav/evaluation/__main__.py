"""``python -m quatnav.evaluation [options]``: the same as ``quatnav bench [options]``."""
import sys

from ..cli import main

sys.exit(main(["bench", *sys.argv[1:]]))
