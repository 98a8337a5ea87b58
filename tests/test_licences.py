"""The licence of every runtime dependency of the default install, and no copyleft among them.

The default install is what ``pip install morphserve`` brings: the distributions named by
morphserve's own ``Requires-Dist`` without an extra, and theirs, recursively (with the
extras a requirement asks for, and markers evaluated for this machine). Each one's licence
is read from its metadata: the SPDX ``License-Expression`` when there is one, else the
``License :: `` classifiers, else the ``License`` field (a name, or the licence's text,
recognised by its opening), else the licence files it ships.

The policy, for the default install only (an optional extra such as ``cholmod``, which
brings CHOLMOD under the GPL through cvxopt and cholespy, is the user's choice and is left
out of the walk):

* accepted: permissive licences (MIT, BSD, Apache-2.0, ISC, PSF, Zlib, Unlicense, ...);
  MPL-2.0 too: its copyleft is per file and binds only changes to its own files, which we
  ship unmodified (certifi, part of orjson);
* refused as a distribution's licence: GPL, AGPL and LGPL in any version, and the other
  strong or network copyleft licences (SSPL, EUPL, OSL, CC-BY-SA). LGPL is refused too,
  although using it as a separately loaded library is usually acceptable: no dependency
  needs it, and a Python package under LGPL leaves the user to check what "linking" means
  for Python code;
* a choice (``A OR B``) is accepted when one side is; a ``WITH`` runtime exception that
  frees what is built with the code (GCC-exception, Classpath-exception, LLVM-exception)
  makes the GPL it qualifies acceptable;
* the libraries a wheel bundles are listed under it, from its licence files' ``Name:`` /
  ``Files:`` / ``License:`` blocks and from the shared libraries auditwheel grafted into
  ``<package>.libs/``. The same rules hold, with one exception made explicit: an LGPL
  *shared library*, a separate file loaded at run time, is accepted. That is libquadmath
  (LGPL-2.1-or-later, GCC's) inside the NumPy and SciPy wheels: dynamic linking
  to a replaceable library is what the LGPL allows without extending it to the program,
  and NumPy and SciPy are the base of the package, so no permissive install exists
  without it;
* a licence file need not name what a wheel compiles into its own extension modules:
  cholespy's metadata and licence file say BSD-3-Clause, and its extension module holds
  CHOLMOD's Supernodal module (GPL-2.0-or-later). So every compiled file is searched for
  the entry points of the copyleft libraries that numerical wheels are known to build in
  (:data:`COMPILED_IN`: SuiteSparse's CHOLMOD, UMFPACK, SPQR and KLU, FFTW, GSL,
  Readline), and what it finds is listed and judged like any bundled library;
* a licence that cannot be read at all fails too: every dependency must be accounted for.

Run as a script (``make licences``) to print the table.
"""

from __future__ import annotations

import importlib.metadata as md
import re
import sys
import tomllib
from dataclasses import dataclass
from pathlib import Path

import pytest
from packaging.requirements import Requirement
from packaging.utils import canonicalize_name

ROOT = Path(__file__).resolve().parents[1]

#: SPDX identifiers accepted as they are (lower case); ``-only``/``-or-later`` suffixes of
#: the GNU family are refused by COPYLEFT below whatever their version
PERMISSIVE = {
    "mit", "mit-0", "mit-cmu", "bsd", "bsd-2-clause", "bsd-3-clause", "bsd-3-clause-clear",
    "0bsd", "apache-2.0", "apache", "isc", "psf-2.0", "python-2.0", "zlib", "unlicense",
    "cc0-1.0", "hpnd", "zpl-2.1", "bsl-1.0", "wtfpl", "ncsa", "upl-1.0", "x11", "curl",
    "bsd-3-clause-open-mpi", "mpl-2.0",  # MPL: file-level copyleft only: accepted (see the module docstring)
}
COPYLEFT = re.compile(r"\b(a?gpl|lgpl|gfdl|sspl|eupl|osl|cc-by-sa|cpal|rpl|sleepycat)", re.I)
#: exceptions that free what is built with the licensed code
RUNTIME_EXCEPTIONS = {"gcc-exception-3.1", "gcc-exception-2.0", "classpath-exception-2.0",
                      "llvm-exception"}
#: ``License :: OSI Approved :: ...`` classifiers -> SPDX
CLASSIFIERS = {
    "MIT License": "MIT", "MIT No Attribution License (MIT-0)": "MIT-0",
    "BSD License": "BSD", "Apache Software License": "Apache-2.0",
    "ISC License (ISCL)": "ISC", "Python Software Foundation License": "PSF-2.0",
    "Mozilla Public License 2.0 (MPL 2.0)": "MPL-2.0", "The Unlicense (Unlicense)": "Unlicense",
    "zlib/libpng License": "Zlib", "Historical Permission Notice and Disclaimer (HPND)": "HPND",
    "Zope Public License": "ZPL-2.1", "Boost Software License 1.0 (BSL-1.0)": "BSL-1.0",
    "Universal Permissive License (UPL)": "UPL-1.0",
    "GNU General Public License v2 (GPLv2)": "GPL-2.0",
    "GNU General Public License v3 (GPLv3)": "GPL-3.0",
    "GNU General Public License v2 or later (GPLv2+)": "GPL-2.0-or-later",
    "GNU General Public License v3 or later (GPLv3+)": "GPL-3.0-or-later",
    "GNU General Public License (GPL)": "GPL",
    "GNU Lesser General Public License v2 (LGPLv2)": "LGPL-2.0",
    "GNU Lesser General Public License v3 (LGPLv3)": "LGPL-3.0",
    "GNU Lesser General Public License v2 or later (LGPLv2+)": "LGPL-2.0-or-later",
    "GNU Lesser General Public License v3 or later (LGPLv3+)": "LGPL-3.0-or-later",
    "GNU Library or Lesser General Public License (LGPL)": "LGPL",
    "GNU Affero General Public License v3": "AGPL-3.0",
    "GNU Affero General Public License v3 or later (AGPLv3+)": "AGPL-3.0-or-later",
}
#: a licence's text or free-form name, recognised by a phrase (the first match wins)
PHRASES = [
    (re.compile(r"GNU Affero General Public License", re.I), "AGPL"),
    (re.compile(r"GNU (Lesser|Library) General Public License", re.I), "LGPL"),
    (re.compile(r"GNU General Public License", re.I), "GPL"),
    (re.compile(r"Mozilla Public License,? (Version )?2\.0", re.I), "MPL-2.0"),
    (re.compile(r"Apache License,? (Version )?2\.0|^Apache[ -]2(\.0)?$|^Apache Software License$",
                re.I), "Apache-2.0"),
    (re.compile(r"Permission is hereby granted, free of charge|^MIT( License)?$", re.I), "MIT"),
    (re.compile(r"Redistribution and use in source and binary forms|^(new |modified |3-clause "
                r"|simplified )?BSD( License)?$|^BSD[- ][23]-Clause$", re.I), "BSD"),
    (re.compile(r"^ISC( License)?$|Permission to use, copy, modify, and(/or)? distribute", re.I),
     "ISC"),
]


def accepted(expression: str) -> bool:
    """Whether an SPDX licence expression is acceptable in the default install.

    ``OR`` takes the better side, ``AND`` needs both, ``X WITH exception`` is ``X`` unless
    the exception is a runtime one; an unknown identifier is not acceptable.
    """
    tokens = re.findall(r"\(|\)|[^\s()]+", expression)
    pos = 0

    def peek() -> str:
        return tokens[pos].upper() if pos < len(tokens) else ""

    def atom() -> bool:
        nonlocal pos
        if peek() == "(":
            pos += 1
            value = either()
            pos += 1  # ")"
            return value
        ident = tokens[pos].lower()
        pos += 1
        if peek() == "WITH":
            exception = tokens[pos + 1].lower()
            pos += 2
            if exception in RUNTIME_EXCEPTIONS:
                return True
        ident = ident.removesuffix("+")
        return ident in PERMISSIVE and not COPYLEFT.search(ident)

    def both() -> bool:
        nonlocal pos
        value = atom()
        while peek() == "AND":
            pos += 1
            value = atom() and value
        return value

    def either() -> bool:
        nonlocal pos
        value = both()
        while peek() == "OR":
            pos += 1
            value = both() or value
        return value

    return bool(tokens) and either() and pos == len(tokens)


def from_text(text: str) -> str | None:
    """The licence a name or a licence's text gives, by its opening, or None."""
    text = text.strip()
    if not text or text.upper() in ("UNKNOWN", "NONE"):
        return None
    opening = " ".join(text[:1500].split())
    if len(text) < 80 and "\n" not in text and re.fullmatch(r"[\w.+\- ()]+", text) \
            and accepted(text):
        return text  # already an acceptable SPDX expression
    for pattern, name in PHRASES:
        if pattern.search(opening):
            return name
    if len(text) < 80 and COPYLEFT.search(text):
        return text
    return None


def licence_of(dist: md.Distribution) -> tuple[str, str]:
    """``(licence, where it was read)`` of an installed distribution; ``("?", ...)`` when it
    says none that can be recognised."""
    meta = dist.metadata
    expression = meta.get("License-Expression")
    if expression:
        return expression.strip(), "License-Expression"
    names = [c.split(" :: ")[-1] for c in meta.get_all("Classifier") or []
             if c.startswith("License :: ")]
    known = [CLASSIFIERS[n] for n in names if n in CLASSIFIERS]
    if known and len(known) == len(names):
        # several classifiers: all of them must be acceptable (read as AND, the safe side)
        return " AND ".join(dict.fromkeys(known)), "classifiers"
    field = meta.get("License") or ""
    name = from_text(field)
    if name:
        return name, "License"
    for f in dist.files or []:
        if re.search(r"(LICEN[CS]E|COPYING)", f.name, re.I) and ".dist-info" in str(f):
            text = Path(f.locate()).read_text(encoding="utf-8", errors="replace")
            name = from_text(text)
            if name:
                return name, f"file {f.name}"
    return "?", "none found"


#: shared libraries that auditwheel grafts into wheels (``<package>.libs/``) and that the
#: wheel's metadata may not name, by file name stem
GRAFTED = {
    "libgfortran": "GPL-3.0-or-later WITH GCC-exception-3.1",
    "libgomp": "GPL-3.0-or-later WITH GCC-exception-3.1",
    "libgcc_s": "GPL-3.0-or-later WITH GCC-exception-3.1",
    "libstdc++": "GPL-3.0-or-later WITH GCC-exception-3.1",
    "libquadmath": "LGPL-2.1-or-later",
    "libscipy_openblas": "BSD-3-Clause", "libscipy_openblas64_": "BSD-3-Clause",
    "libopenblas": "BSD-3-Clause",
    "libblas": "BSD-3-Clause-Open-MPI", "liblapack": "BSD-3-Clause-Open-MPI",  # reference
}
#: a separate shared library (``libquadmath-1a2b.so.0``, ``libx*.so``), not a Python
#: extension module (``_ext.cpython-311-x86_64-linux-gnu.so``), which is the package's own code
SHARED_LIBRARY = re.compile(r"(^|/)lib(?!.*(cpython|abi3|pypy))[^/]*\.(so|dylib)(\*|\.[\d*]+)*$")
#: copyleft libraries that a wheel may compile into its own extension modules, where neither
#: a licence file nor a grafted library names them (cholespy's wheels compile in CHOLMOD):
#: recognised by an entry point's name, which a compiled file holds whether it contains
#: the library or links to it -> (library, licence)
COMPILED_IN = {
    b"cholmod_super_numeric": ("CHOLMOD Supernodal", "GPL-2.0-or-later"),
    b"cholmod_updown": ("CHOLMOD Modify", "GPL-2.0-or-later"),
    b"cholmod_start": ("CHOLMOD Core", "LGPL-2.1-or-later"),
    b"cholmod_l_start": ("CHOLMOD Core", "LGPL-2.1-or-later"),
    b"umfpack_di_numeric": ("UMFPACK", "GPL-2.0-or-later"),
    b"umfpack_dl_numeric": ("UMFPACK", "GPL-2.0-or-later"),
    b"SuiteSparseQR": ("SPQR", "GPL-2.0-or-later"),
    b"klu_factor": ("KLU", "LGPL-2.1-or-later"),
    b"klu_l_factor": ("KLU", "LGPL-2.1-or-later"),
    b"fftw_execute": ("FFTW", "GPL-2.0-or-later"),
    b"gsl_set_error_handler": ("GSL", "GPL-3.0-or-later"),
    b"rl_readline_version": ("GNU Readline", "GPL-3.0-or-later"),
}
#: a compiled file: an extension module or a shared library
COMPILED = re.compile(r"\.(so|pyd|dylib)(\.[\d.]+)*$")
#: the bundled-licence blocks of NumPy's and SciPy's licence files
BLOCK = re.compile(r"^Name: (?P<name>.+)\nFiles: (?P<files>.+)\n(?:\w+: .*\n)*?License: "
                   r"(?P<licence>.+)$", re.M)


@dataclass
class Bundled:
    """A library inside a distribution's wheel, with its own licence."""

    name: str
    files: str
    licence: str

    @property
    def dynamic_lgpl(self) -> bool:
        """An LGPL shared library loaded at run time (a separate, replaceable file)."""
        return bool(re.fullmatch(r"LGPL-[\d.]+(-only|-or-later|\+)?", self.licence)) and all(
            SHARED_LIBRARY.search(f.strip()) for f in self.files.split(","))

    @property
    def ok(self) -> bool:
        return accepted(self.licence) or self.dynamic_lgpl


def bundled_of(dist: md.Distribution) -> list[Bundled]:
    """The libraries a distribution bundles: those its licence files list (``Name:``,
    ``Files:``, ``License:`` blocks) and the shared libraries grafted into it by
    auditwheel, which a licence file need not name (``"?"`` when unknown)."""
    out: list[Bundled] = []
    texts = [dist.metadata.get("License") or ""]
    texts += [Path(f.locate()).read_text(encoding="utf-8", errors="replace") for f in dist.files or []
              if ".dist-info" in str(f) and re.search(r"LICEN[CS]E|COPYING", f.name, re.I)]
    for text in texts:
        for m in BLOCK.finditer(text):
            b = Bundled(m["name"].strip(), m["files"].strip(), m["licence"].strip())
            if b not in out:
                out.append(b)
    import fnmatch

    for f in dist.files or []:
        if not (len(f.parts) == 2 and f.parts[0].endswith(".libs")):
            continue
        path = f.as_posix()
        if any(fnmatch.fnmatch(path, pat.strip() + "*")  # libx*.so covers libx-1a2b.so.5
               for b in out for pat in b.files.split(",")):
            continue
        stem = re.sub(r"(-[0-9a-f]{8})+(\.so.*)?$|(\.so.*)$", "", f.name)
        out.append(Bundled(stem, path, GRAFTED.get(stem, "?")))
    return out + compiled_in(dist)


def compiled_in(dist: md.Distribution) -> list[Bundled]:
    """The copyleft libraries of :data:`COMPILED_IN` that a distribution's own compiled
    files (not those grafted into ``<package>.libs/``, which :func:`bundled_of` names by
    file) contain or link to."""
    import mmap

    out: list[Bundled] = []
    for f in dist.files or []:
        if not COMPILED.search(f.name) or f.parts[0].endswith(".libs"):
            continue
        path = Path(f.locate())
        if not path.is_file() or path.stat().st_size == 0:
            continue
        with path.open("rb") as fh, mmap.mmap(fh.fileno(), 0, access=mmap.ACCESS_READ) as data:
            for symbol, (library, licence) in COMPILED_IN.items():
                b = Bundled(library, f.as_posix(), licence)
                if b not in out and data.find(symbol) >= 0:
                    out.append(b)
    return out


@dataclass
class Dependency:
    name: str
    version: str
    licence: str
    source: str
    required_by: list[str]
    bundled: list[Bundled]

    @property
    def ok(self) -> bool:
        return accepted(self.licence) and all(b.ok for b in self.bundled)


def default_install(root: str = "morphserve") -> list[Dependency]:
    """Every distribution the default install of ``root`` brings (without ``root``), by
    walking ``Requires-Dist`` without extras; raises when one is not installed."""
    found: dict[str, Dependency] = {}
    queue: list[tuple[str, frozenset[str], str]] = [(root, frozenset(), "")]
    seen: set[tuple[str, frozenset[str]]] = set()
    while queue:
        name, extras, parent = queue.pop(0)
        key = canonicalize_name(name)
        if key in found and parent:
            if parent not in found[key].required_by:
                found[key].required_by.append(parent)
        if (key, extras) in seen:
            continue
        seen.add((key, extras))
        try:
            dist = md.distribution(name)
        except md.PackageNotFoundError:
            raise AssertionError(f"{name} (required by {parent}) is not installed") from None
        if key != canonicalize_name(root) and key not in found:
            licence, source = licence_of(dist)
            found[key] = Dependency(dist.metadata["Name"], dist.version, licence, source,
                                    [parent], bundled_of(dist))
        for line in dist.requires or []:
            req = Requirement(line)
            if req.marker is not None and not any(
                    req.marker.evaluate({"extra": e}) for e in (extras or {""})):
                continue
            queue.append((req.name, frozenset(req.extras), dist.metadata["Name"]))
    return sorted(found.values(), key=lambda d: d.name.lower())


def table(deps: list[Dependency]) -> str:
    rows = [("distribution", "version", "licence", "verdict", "read from", "required by")]
    for d in deps:
        rows.append((d.name, d.version, d.licence, "ok" if accepted(d.licence) else "REFUSED",
                     d.source, ", ".join(d.required_by)))
        for b in d.bundled:
            verdict = ("ok (LGPL, linked dynamically)" if b.dynamic_lgpl
                       else "ok" if b.ok else "REFUSED")
            rows.append((f"  + {b.name}", "", b.licence, verdict, f"bundled: {b.files}", ""))
    widths = [max(len(r[i]) for r in rows) for i in range(len(rows[0]))]
    lines = ["  ".join(c.ljust(w) for c, w in zip(r, widths)).rstrip() for r in rows]
    lines.insert(1, "  ".join("-" * w for w in widths).rstrip())
    return "\n".join(lines)


# --- the tests ----------------------------------------------------------------------------


def test_installed_requirements_are_pyproject_s():
    # the walk starts from the installed metadata: it must be that of this pyproject.toml
    project = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]
    declared = {str(Requirement(r)) for r in project["dependencies"]}
    installed = {str(r) for r in map(Requirement, md.requires("morphserve") or [])
                 if r.marker is None or "extra" not in str(r.marker)}
    assert installed == declared, "stale install: run `pip install -e .` (make does it)"


def test_default_install_has_no_copyleft_licence(capsys):
    deps = default_install()
    with capsys.disabled():  # the list, in the test run's output
        print(f"\nthe default install: {len(deps)} distributions\n{table(deps)}")
    names = {canonicalize_name(d.name) for d in deps}
    assert {"numpy", "scipy", "fastapi", "distributed", "pot"} <= names
    assert not names & {"cvxopt", "cholespy"}  # CHOLMOD is the cholmod extra only
    refused = [f"{d.name} {d.version}: {d.licence} ({d.source})" for d in deps
               if not accepted(d.licence)]
    refused += [f"{b.name} in {d.name} {d.version}: {b.licence} ({b.files})" for d in deps
                for b in d.bundled if not b.ok]
    assert not refused, "copyleft or unreadable licences in the default install:\n" + \
        "\n".join(refused)


def test_bundled_libraries_of_numpy_are_read():
    # NumPy's own licence file lists its bundled libraries; the grafted ones are all named
    numpy = {b.name: b for b in bundled_of(md.distribution("numpy"))}
    assert numpy["libquadmath"].licence == "LGPL-2.1-or-later"
    assert numpy["libquadmath"].dynamic_lgpl and numpy["libquadmath"].ok
    assert numpy["GCC runtime library"].licence == "GPL-3.0-or-later WITH GCC-exception-3.1"
    assert all(b.licence != "?" for b in numpy.values())


def test_bundled_library_rules(tmp_path, monkeypatch):
    _fake_dist(tmp_path, "fake-wheel", "License-Expression: MIT",
               files=["fake_wheel.libs/libgomp-1a2b3c4d.so.1.0.0",
                      "fake_wheel.libs/libquadmath-1a2b3c4d.so.0.0.0",
                      "fake_wheel.libs/libmystery-1a2b3c4d.so.2"])
    _fake_dist(tmp_path, "fake-static", "License-Expression: MIT",
               license_text="Name: somelib\nFiles: fake_static/_ext.cpython-311.so\n"
                            "License: LGPL-3.0-or-later\n")
    monkeypatch.syspath_prepend(str(tmp_path))
    wheel = {b.name: b for b in bundled_of(md.distribution("fake-wheel"))}
    assert wheel["libgomp"].ok and wheel["libquadmath"].dynamic_lgpl
    assert wheel["libmystery"].licence == "?" and not wheel["libmystery"].ok
    # LGPL code compiled into the package's own extension: not a separate library
    (static,) = bundled_of(md.distribution("fake-static"))
    assert static.licence == "LGPL-3.0-or-later" and not static.ok
    assert not static.dynamic_lgpl


def test_compiled_in_copyleft_is_found(tmp_path, monkeypatch):
    # an MIT wheel whose extension module carries CHOLMOD's supernodal code, and one whose
    # extension module carries nothing known: only the first is refused
    _fake_dist(tmp_path, "fake-static-gpl", "License-Expression: MIT",
               files={"fake_static_gpl/_core.cpython-311-x86_64-linux-gnu.so":
                      b"\x7fELF\0...cholmod_start\0cholmod_super_numeric\0..."})
    _fake_dist(tmp_path, "fake-clean", "License-Expression: MIT",
               files={"fake_clean/_core.cpython-311-x86_64-linux-gnu.so": b"\x7fELF\0dgemm_\0"})
    monkeypatch.syspath_prepend(str(tmp_path))
    found = {b.name: b for b in bundled_of(md.distribution("fake-static-gpl"))}
    assert sorted(found) == ["CHOLMOD Core", "CHOLMOD Supernodal"]
    assert found["CHOLMOD Supernodal"].licence == "GPL-2.0-or-later"
    assert not found["CHOLMOD Supernodal"].ok
    assert not found["CHOLMOD Core"].ok and not found["CHOLMOD Core"].dynamic_lgpl  # static
    assert bundled_of(md.distribution("fake-clean")) == []


def test_cholespy_is_found_to_carry_cholmod_when_installed():
    # the real case: cholespy's metadata says BSD, its extension module is CHOLMOD's
    try:
        dist = md.distribution("cholespy")
    except md.PackageNotFoundError:
        pytest.skip("cholespy (the cholmod extra) not installed")
    assert accepted(licence_of(dist)[0])  # the metadata alone would let it through
    found = {b.name for b in bundled_of(dist) if not b.ok}
    assert "CHOLMOD Supernodal" in found


@pytest.mark.parametrize("dist", ["cvxopt", "cholespy"])
def test_cholmod_is_an_extra(dist):
    reqs = [Requirement(r) for r in md.requires("morphserve") or []]
    declared = [r for r in reqs if canonicalize_name(r.name) == dist]
    assert declared, f"{dist} is declared by an extra"
    for r in declared:
        assert r.marker is not None and not r.marker.evaluate({"extra": ""})
    assert any(r.marker.evaluate({"extra": "cholmod"}) for r in declared if r.marker)


def test_vendored_browser_assets_ship_their_licences():
    # the image installs morphserve's wheel: a licence file is in it exactly when a
    # package-data pattern of the service package matches it
    import fnmatch

    patterns = tomllib.loads((ROOT / "pyproject.toml").read_text())["tool"]["setuptools"][
        "package-data"]["service"]
    static = ROOT / "service" / "static"
    vendored = [d for d in (static / "vendor").iterdir() if d.is_dir()] + [static / "swagger"]
    assert len(vendored) >= 2
    for folder in vendored:
        licences = [f for f in folder.iterdir() if re.match(r"(LICEN[CS]E|COPYING|NOTICE)", f.name)]
        assert licences, f"{folder.relative_to(ROOT)} has no licence file"
        for f in licences:
            rel = f.relative_to(ROOT / "service").as_posix()
            assert any(fnmatch.fnmatch(rel, pat) for pat in patterns), \
                f"{rel} is not package data: the wheel and the image would lack it"


def _fake_dist(site: Path, name: str, *headers: str,
               files: tuple[str, ...] | list[str] | dict[str, bytes] = (),
               license_text: str = "") -> None:
    """An installed distribution in ``site``: its metadata, the ``files`` (empty, or with
    the contents a dict gives) and a licence file holding ``license_text``, all in its
    RECORD."""
    stem = name.replace("-", "_")
    info = site / f"{stem}-1.0.dist-info"
    info.mkdir()
    (info / "METADATA").write_text("\n".join(["Metadata-Version: 2.4", f"Name: {name}",
                                              "Version: 1.0", *headers]) + "\n")
    record = [f"{info.name}/METADATA,,"]
    for rel in files:
        (site / rel).parent.mkdir(parents=True, exist_ok=True)
        (site / rel).write_bytes(files[rel] if isinstance(files, dict) else b"")
        record.append(f"{rel},,")
    if license_text:
        (info / "LICENSE").write_text(license_text)
        record.append(f"{info.name}/LICENSE,,")
    (info / "RECORD").write_text("\n".join(record) + "\n")


def test_walk_finds_copyleft_below_and_skips_extras(tmp_path, monkeypatch):
    # root -> permissive -> gpl (found two levels down); root's extra -> lgpl (left out)
    _fake_dist(tmp_path, "fake-root", "License-Expression: MIT",
               "Requires-Dist: fake-permissive>=1", 'Requires-Dist: fake-lgpl; extra == "opt"')
    _fake_dist(tmp_path, "fake-permissive", "Classifier: License :: OSI Approved :: MIT License",
               "Requires-Dist: fake-gpl[cli]")
    _fake_dist(tmp_path, "fake-gpl", "License: GPL-3.0-or-later",
               'Requires-Dist: fake-agpl; extra == "cli"')
    _fake_dist(tmp_path, "fake-agpl", "License: GNU Affero General Public License v3")
    _fake_dist(tmp_path, "fake-lgpl", "License-Expression: LGPL-2.1-only")
    monkeypatch.syspath_prepend(str(tmp_path))
    deps = {d.name: d for d in default_install("fake-root")}
    assert sorted(deps) == ["fake-agpl", "fake-gpl", "fake-permissive"]
    assert deps["fake-permissive"].ok and deps["fake-permissive"].required_by == ["fake-root"]
    assert not deps["fake-gpl"].ok and deps["fake-gpl"].licence == "GPL-3.0-or-later"
    assert not deps["fake-agpl"].ok and deps["fake-agpl"].licence == "AGPL"


@pytest.mark.parametrize(("expression", "ok"), [
    ("MIT", True), ("BSD-3-Clause", True), ("Apache-2.0 OR BSD-2-Clause", True),
    ("MPL-2.0 AND (Apache-2.0 OR MIT)", True), ("MIT OR GPL-3.0-only", True),
    ("GPL-3.0-or-later", False), ("GPL-2.0+", False), ("AGPL-3.0-only", False),
    ("LGPL-2.1-or-later", False), ("LGPL-3.0-only OR LGPL-2.1-only", False),
    ("MIT AND GPL-2.0-only", False), ("(MIT AND LGPL-3.0-only) OR BSD-2-Clause", True),
    ("GPL-3.0-or-later WITH GCC-exception-3.1", True),
    ("GPL-2.0-only WITH Linux-syscall-note", False), ("SSPL-1.0", False),
    ("LicenseRef-Proprietary", False), ("", False),
])
def test_expression_policy(expression, ok):
    assert accepted(expression) is ok


@pytest.mark.parametrize(("text", "name"), [
    ("MIT", "MIT"), ("Apache 2.0", "Apache-2.0"), ("BSD", "BSD"), ("new BSD License", "BSD"),
    ("Copyright (c) 2020 X\n\nPermission is hereby granted, free of charge, to any person",
     "MIT"),
    ("Copyright X. All rights reserved.\n\nRedistribution and use in source and binary forms,"
     " with or without modification", "BSD"),
    ("This program is free software; you can redistribute it and/or modify it under the terms"
     " of the GNU General Public License as published by the Free Software Foundation", "GPL"),
    ("under the terms of the GNU Lesser General Public License", "LGPL"),
    ("UNKNOWN", None), ("", None), ("All rights reserved.", None),
])
def test_licence_text_is_recognised(text, name):
    assert from_text(text) == name


def test_cvxopt_is_read_as_gpl_when_installed():
    # the one copyleft distribution we know of: its metadata has only the licence's text
    try:
        dist = md.distribution("cvxopt")
    except md.PackageNotFoundError:
        pytest.skip("cvxopt (the cholmod extra) not installed")
    licence, _ = licence_of(dist)
    assert COPYLEFT.search(licence) and not accepted(licence)


if __name__ == "__main__":
    deps = default_install()
    print(f"The default install of morphserve: {len(deps)} distributions "
          "(optional extras not included)\n")
    print(table(deps))
    bad = [d for d in deps if not d.ok]
    print(f"\n{len(bad)} refused" if bad else "\nno copyleft licence but LGPL shared "
          "libraries (bundled, loaded at run time) and runtime-exception GPL")
    sys.exit(1 if bad else 0)
