"""``python -m urdfinertia``: the ``urdf-inertia`` command."""

import sys

from urdfinertia.cli import main

sys.exit(main())
