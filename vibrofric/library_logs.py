"""The libraries' own log lines kept off the terminal: only their warnings and errors.

A first FE model build has FFCx compile DOLFINx's forms: it calls
``logging.basicConfig()``, setuptools then lowers the root logger to INFO and logs
every C compiler command line. A clean ``vibrofric`` command (cli.py) and the
set-up's warm-up (warm.py) print only their own lines.
"""

import logging


def quiet_libraries() -> None:
    """Let the root logger's handlers pass warnings and errors only (one added, on
    stderr, where there is none: FFCx's basicConfig then adds none of its own)."""
    root = logging.getLogger()
    if not root.handlers:
        root.addHandler(logging.StreamHandler())
    for handler in root.handlers:
        handler.setLevel(logging.WARNING)
