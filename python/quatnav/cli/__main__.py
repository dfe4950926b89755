"""``python -m quatnav.cli``: the ``quatnav`` command (as ``python -m quatnav``)."""
import sys

from . import main

sys.exit(main())
