"""Test double: a node process that ends at once with status 3 and writes nothing (an empty log)."""

import os

os._exit(3)
