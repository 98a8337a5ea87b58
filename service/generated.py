"""The command line of the service's generated files (``make openapi``, ``make sdk``): write
what a ``render()`` returns to a path, or to stdout. Tests compare the committed copies with
``render()``, so a stale file fails them."""

from __future__ import annotations

import argparse
import sys
from collections.abc import Callable

__all__ = ["main"]


def main(argv: list[str], *, prog: str, description: str, render: Callable[[], str]) -> int:
    parser = argparse.ArgumentParser(prog=prog, description=description)
    parser.add_argument("path", nargs="?", help="where to write it (default: stdout)")
    args = parser.parse_args(argv)  # --help prints this, rather than writing a file so named
    text = render()
    if args.path:
        with open(args.path, "w", encoding="utf-8") as f:
            f.write(text)
    else:
        sys.stdout.write(text)
    return 0
