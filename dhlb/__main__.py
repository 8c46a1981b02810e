"""``python -m dhlb``: the same as the ``dhlb`` command."""

import sys

from dhlb.cli import main

if __name__ == "__main__":
    sys.exit(main())
