"""``python -m planar``: the ``planar`` command (the same as ``python -m planar.cli``)."""

import sys

from planar.cli.main import main

sys.exit(main())
