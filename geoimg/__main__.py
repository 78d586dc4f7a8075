"""``python -m geoimg``: the ``geoimg`` command."""
import sys

from .cli import main

sys.exit(main())
