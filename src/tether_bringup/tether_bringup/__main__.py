"""``python -m tether_bringup``: the ``tethersim`` program."""

import sys

from tether_bringup.cli import main

sys.exit(main())
