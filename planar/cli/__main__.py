"""``python -m planar.cli``: the ``planar`` command."""

import sys

from planar.cli.main import main

sys.exit(main())
