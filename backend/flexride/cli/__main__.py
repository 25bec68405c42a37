"""``python -m flexride.cli``: the ``flexride`` command."""

from flexride.cli import main

main()
