"""``python -m twin.cli``: the same as the ``twin`` command."""

import sys

try:
    from twin.cli import main
except KeyboardInterrupt:   # Ctrl-C while the command line itself is still loading
    print("interrupted: no output written", file=sys.stderr)
    sys.exit(130)

sys.exit(main())
