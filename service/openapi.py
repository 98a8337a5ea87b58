"""Write the service's OpenAPI document: ``python -m service.openapi [PATH]`` (``make openapi``).

The document depends only on the code (the routes and the catalog's response models), not on
settings, so the committed ``openapi/openapi.json`` can be checked against it in a test.
"""

from __future__ import annotations

import json
import sys
from typing import Any

from service.app import create_app
from service.settings import Settings

__all__ = ["document", "render"]


def document() -> dict[str, Any]:
    return create_app(Settings()).openapi()


def render() -> str:
    return json.dumps(document(), indent=2, sort_keys=True, ensure_ascii=False) + "\n"


def main(argv: list[str]) -> int:
    import argparse

    parser = argparse.ArgumentParser(prog="python -m service.openapi",
                                     description="Write the service's OpenAPI document.")
    parser.add_argument("path", nargs="?", help="where to write it (default: stdout)")
    args = parser.parse_args(argv)  # --help prints this, rather than writing a file so named
    text = render()
    if args.path:
        with open(args.path, "w", encoding="utf-8") as f:
            f.write(text)
    else:
        sys.stdout.write(text)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
