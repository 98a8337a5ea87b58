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
    text = render()
    if argv:
        with open(argv[0], "w", encoding="utf-8") as f:
            f.write(text)
    else:
        sys.stdout.write(text)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
