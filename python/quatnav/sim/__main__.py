"""``python -m quatnav.sim [options]``: the same as ``quatnav simulate [options]``."""
import sys

from ..cli import main

sys.exit(main(["simulate", *sys.argv[1:]]))
