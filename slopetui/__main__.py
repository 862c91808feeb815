import sys

from slopetui.cli import main

sys.exit(main())
