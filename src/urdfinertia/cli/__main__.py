"""``python -m urdfinertia.cli``: the same as the ``urdf-inertia`` command."""

import sys

from urdfinertia.cli import main

sys.exit(main())
