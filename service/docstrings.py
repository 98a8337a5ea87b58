"""Docstrings as the service shows them: numpydoc sections read, reStructuredText made plain.

The algorithms document their parameters and results in numpydoc; the service's process
descriptions (and everything built on them: the OpenAPI document, the SDK) take those texts
from there (:mod:`service.catalog.registry`), so each is written once.
"""

from __future__ import annotations

import inspect
import re

__all__ = ["numpydoc_summary", "numpydoc_section", "numpydoc_entries", "numpydoc_references",
           "plain"]


def numpydoc_summary(doc: str | None) -> tuple[str, str]:
    """The short summary of a numpydoc docstring and the first paragraph of its extended
    summary, each joined into one line of plain text (``""`` where there is none).

    A process takes its title and description from them: the short summary names the
    method ("Rigid alignment (Kabsch / Umeyama without scale)."), the paragraph after it
    says what it computes."""
    paragraphs: list[list[str]] = [[]]
    for ln in inspect.cleandoc(doc or "").splitlines():
        if ln.strip():
            paragraphs[-1].append(ln.strip())
        elif paragraphs[-1]:
            paragraphs.append([])
    first = paragraphs[1] if len(paragraphs) > 1 else []
    if len(first) > 1 and set(first[1]) == {"-"}:  # a section's title and underline
        first = []
    return plain(" ".join(paragraphs[0])), plain(" ".join(first))


def numpydoc_section(doc: str | None, title: str) -> dict[str, str]:
    """``name : type`` entries of a numpydoc section and their (joined) descriptions.

    ``a, b : int`` documents both names with one description. Continuation lines are joined
    with spaces; a blank line inside a description becomes a paragraph break."""
    return {n: desc for n, (_, desc) in numpydoc_entries(doc, title).items()}


def _section(doc: str | None, title: str) -> list[str]:
    """The lines of the numpydoc section ``title`` (below its underline, up to the next
    section's title), or none."""
    if not doc:
        return []
    lines = inspect.cleandoc(doc).splitlines()
    try:
        start = next(i for i, ln in enumerate(lines)
                     if ln.strip() == title and i + 1 < len(lines)
                     and set(lines[i + 1].strip()) == {"-"})
    except StopIteration:
        return []
    body = lines[start + 2:]
    for i, ln in enumerate(body):
        nxt = body[i + 1].strip() if i + 1 < len(body) else ""
        if ln.strip() and not ln.startswith(" ") and nxt and set(nxt) == {"-"}:
            return body[:i]
    return body


def numpydoc_entries(doc: str | None, title: str) -> dict[str, tuple[str, str]]:
    """Like :func:`numpydoc_section`, with each entry's type as written (``(n, d) float
    array, optional``) beside its description."""
    out: dict[str, tuple[str, list[str]]] = {}
    names: list[str] = []
    for ln in _section(doc, title):
        m = re.match(r"^(\w+(?:\s*,\s*\w+)*)\s*(?::\s*(.*))?$", ln)
        if m and not ln.startswith(" ") and ln.strip():
            names = [n.strip() for n in m.group(1).split(",")]
            for n in names:
                out[n] = ((m.group(2) or "").strip(), [])
        elif names:
            for n in names:
                out[n][1].append(ln.strip())
    return {n: (kind, _join(parts)) for n, (kind, parts) in out.items()}


def _join(lines: list[str]) -> str:
    paragraphs, current = [], []
    for ln in lines:
        if ln:
            current.append(ln)
        elif current:
            paragraphs.append(" ".join(current))
            current = []
    if current:
        paragraphs.append(" ".join(current))
    return "\n\n".join(paragraphs)


_LATEX = {
    "alpha": "α", "beta": "β", "gamma": "γ", "delta": "δ", "epsilon": "ε", "varepsilon": "ε",
    "lambda": "λ", "mu": "μ", "nu": "ν", "sigma": "σ", "theta": "θ", "omega": "ω", "pi": "π",
    "tau": "τ", "phi": "φ", "rho": "ρ", "eta": "η", "kappa": "κ", "Sigma": "Σ", "Delta": "Δ",
    "le": "≤", "leq": "≤", "ge": "≥", "geq": "≥", "ne": "≠", "neq": "≠", "cdot": "·",
    "times": "×", "infty": "∞", "sum": "Σ", "lVert": "‖", "rVert": "‖", "|": "‖",
    "approx": "≈", "in": "∈", "to": "→", "propto": "∝", "partial": "∂", "nabla": "∇",
    "sqrt": "√", "ldots": "…", "dots": "…", "cdots": "⋯", "top": "ᵀ", "circ": "∘", "pm": "±",
    "leftarrow": "←", "rightarrow": "→", "mapsto": "↦", "Rightarrow": "⇒", "odot": "⊙",
    "forall": "∀", "exists": "∃", "subset": "⊂", "cup": "∪", "cap": "∩", "emptyset": "∅",
}
_SUPERSCRIPT_CHARS = "0123456789-+=()Tni"
_SUPERSCRIPT = str.maketrans(_SUPERSCRIPT_CHARS, "⁰¹²³⁴⁵⁶⁷⁸⁹⁻⁺⁼⁽⁾ᵀⁿⁱ")
_SUBSCRIPT_CHARS = "0123456789aehijklmnoprstuvx+-="
_SUBSCRIPT = str.maketrans(_SUBSCRIPT_CHARS, "₀₁₂₃₄₅₆₇₈₉ₐₑₕᵢⱼₖₗₘₙₒₚᵣₛₜᵤᵥₓ₊₋₌")


def _raise(m: re.Match[str]) -> str:
    """A superscript raised when Unicode has every character of it, else ``^(...)``."""
    sup = m.group(1)
    if all(c in _SUPERSCRIPT_CHARS for c in sup):
        return sup.translate(_SUPERSCRIPT)
    return f"^{sup}" if len(sup) == 1 else f"^({sup})"


def _lower(m: re.Match[str]) -> str:
    """A subscript lowered when Unicode has every character of it, else ``_(...)``."""
    sub = m.group(1) if m.group(1) is not None else m.group(2)
    if all(c in _SUBSCRIPT_CHARS for c in sub):
        return sub.translate(_SUBSCRIPT)
    return f"_({sub})"


def _math(expr: str) -> str:
    """A LaTeX formula as readable plain text: Greek letters and relations as Unicode,
    simple superscripts raised, other commands and braces dropped."""
    expr = re.sub(r"\\[dt]?frac\{([^{}]*)\}\{([^{}]*)\}",
                  lambda m: "/".join(p if p.isalnum() else f"({p})" for p in m.groups()), expr)
    expr = re.sub(r"\\(?:operatorname|mathrm|mathbf|mathbb|mathsf|text|mathcal)\{([^{}]*)\}",
                  r"\1", expr)
    expr = re.sub(r"\\lVert\s*", "‖", expr)
    expr = re.sub(r"\s*\\rVert", "‖", expr)
    expr = re.sub(r"\\(?:left|right|big|Big|bigl|bigr)(?![a-zA-Z])", "", expr)
    expr = re.sub(r"\\[,;!:]|\\quad|\\qquad|~", " ", expr)
    expr = re.sub(r"\\hat\s*\{?(?:\\([a-zA-Z]+)|(\w))\}?",
                  lambda m: (_LATEX.get(m.group(1), m.group(1)) if m.group(1) else m.group(2))
                  + "\u0302", expr)
    expr = re.sub(r"\\(?:tilde|bar|hat)\s*", "", expr)
    expr = re.sub(r"\\([a-zA-Z]+|\|)", lambda m: _LATEX.get(m.group(1), m.group(1)), expr)
    expr = re.sub(r"\^(?!\{)([0-9A-Za-z])", _raise, expr)  # x^2 first, then ^{...}
    expr = re.sub(r"\^\{([^{}]*)\}", _raise, expr)
    expr = re.sub(r"_\{([^{}]*)\}|_([0-9a-z])(?![0-9a-zA-Z])", _lower, expr)
    expr = expr.replace("{", "").replace("}", "")
    return re.sub(r"\s+", " ", expr).strip()


def plain(text: str) -> str:
    """reStructuredText of a docstring as the plain text (with Markdown code spans) of a
    process description: ````x```` and cross-references become ```x```, :math: roles
    readable formulas."""
    text = re.sub(r":math:`([^`]*)`", lambda m: _math(m.group(1)), text)
    text = re.sub(r":(?:\w+:)?\w+:`~?(?:[\w.]*\.)?([^`<]*?)(?:\s*<[^>]*>)?`",
                  lambda m: f"`{m.group(1)}`", text)
    text = re.sub(r"``([^`]+)``", r"`\1`", text)
    text = re.sub(r"\s*\[\d+\]_", "", text)  # citations: the process lists its references
    return text.replace("\\ ", "").strip()


def numpydoc_references(doc: str | None) -> list[str]:
    """The entries of a numpydoc ``References`` section (``.. [1] A. Author, "Title", ...``),
    each joined into one line of plain text, in order."""
    refs: list[list[str]] = []
    for ln in _section(doc, "References"):
        m = re.match(r"^\.\. \[[^\]]+\]\s*(.*)$", ln)
        if m:
            refs.append([m.group(1).strip()])
        elif refs and ln.strip():
            refs[-1].append(ln.strip())
    return [plain(" ".join(parts)) for parts in refs]
