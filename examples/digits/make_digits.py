"""Write the workbench's digits sample, ``service/static/ui/sample-digits.json``.

The sample is the first 50 images of each digit, in file order, of scikit-learn's copy of the
UCI "Optical Recognition of Handwritten Digits" test set (``sklearn/datasets/data/digits.csv.gz``,
1,797 images of 8x8 pixels, each pixel a count 0..16), kept as they are: 500 rows of 64
integers and their 500 labels. scikit-learn is a test dependency (``pip install -e '.[test]'``);
it is read here, once, never at run time.

    .venv/bin/python examples/digits/make_digits.py
"""

from __future__ import annotations

import gzip
import hashlib
import json
from pathlib import Path

import numpy as np

PER_CLASS = 50
OUT = Path(__file__).resolve().parents[2] / "service" / "static" / "ui" / "sample-digits.json"


def main() -> None:
    import sklearn.datasets

    source = Path(sklearn.datasets.__file__).parent / "data" / "digits.csv.gz"
    raw = source.read_bytes()
    table = np.loadtxt(gzip.decompress(raw).decode().splitlines(), delimiter=",", dtype=np.int64)
    pixels, labels = table[:, :64], table[:, 64]
    assert table.shape == (1797, 65) and pixels.min() >= 0 and pixels.max() <= 16
    rows = np.concatenate([np.flatnonzero(labels == c)[:PER_CLASS] for c in range(10)])
    rows.sort()  # file order, the classes interleaved as in the original
    head = {
        "title": f"Handwritten digits: {len(rows)} images of 8x8 pixels",
        "description": "Each point is one 8x8 image of a handwritten digit, its 64 pixels "
        "(counts 0..16) read row by row; labels are the digits 0-9.",
        "source": "E. Alpaydin, C. Kaynak (1998). Optical Recognition of Handwritten Digits "
        "[data set]. UCI Machine Learning Repository. https://doi.org/10.24432/C50P49",
        "licence": "CC BY 4.0 (https://creativecommons.org/licenses/by/4.0/)",
        "changes": f"The first {PER_CLASS} images of each digit, in file order, of the test "
        "set as scikit-learn ships it (sklearn/datasets/data/digits.csv.gz, SHA-256 "
        f"{hashlib.sha256(raw).hexdigest()}); values unchanged.",
    }
    lines = ["{"] + [f"  {json.dumps(k)}: {json.dumps(v, ensure_ascii=False)},"
                     for k, v in head.items()]
    lines.append('  "points": [')
    lines += [f"    {json.dumps(pixels[i].tolist(), separators=(',', ':'))}"
              + ("," if n < len(rows) - 1 else "") for n, i in enumerate(rows)]
    lines.append("  ],")
    lines.append(f'  "labels": {json.dumps(labels[rows].tolist(), separators=(",", ":"))}')
    lines.append("}")
    OUT.write_text("\n".join(lines) + "\n", encoding="utf-8")
    print(f"{OUT}: {len(rows)} images, {OUT.stat().st_size} bytes")


if __name__ == "__main__":
    main()
