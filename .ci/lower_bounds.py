"""Print pip constraints pinning each runtime dependency of pyproject.toml to its oldest release.

``python .ci/lower_bounds.py > constraints.txt`` then
``pip install -c constraints.txt -e ".[test]"`` installs, for every package of
``[project] dependencies`` with a lower bound ``>=X``, the oldest release at or above ``X`` that
pip can install here (``pip index versions``: releases with a wheel or sdist for this Python).
Test tools (the extras) stay free: the step checks the library's bounds, not pytest's.
"""

from __future__ import annotations

import re
import subprocess
import sys
from pathlib import Path

import tomllib

try:
    from packaging.version import InvalidVersion, Version
except ImportError:  # a bare environment: pip's own copy
    from pip._vendor.packaging.version import InvalidVersion, Version

ROOT = Path(__file__).resolve().parents[1]


def lower_bounds() -> dict[str, str]:
    """``{name: bound}`` of the runtime dependencies that have a ``>=`` bound."""
    project = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]
    out: dict[str, str] = {}
    for req in project["dependencies"]:
        m = re.match(r"^\s*([A-Za-z0-9_.\-]+)(\[[^\]]*\])?\s*>=\s*([0-9][0-9A-Za-z.\-]*)", req)
        if m:
            out[m.group(1).lower().replace("_", "-")] = m.group(3)
    return out


def oldest_release(name: str, bound: str) -> str:
    """The oldest release of ``name`` at or above ``bound`` that pip can install here."""
    text = subprocess.run(
        [sys.executable, "-m", "pip", "index", "versions", name],
        capture_output=True,
        text=True,
        check=True,
    ).stdout
    listed = re.search(r"Available versions:(.*)", text)
    if not listed:
        raise SystemExit(f"{name}: pip lists no release ({text.strip()[:200]})")
    versions = []
    for v in listed.group(1).split(","):
        try:
            versions.append(Version(v.strip()))
        except InvalidVersion:
            continue
    ok = [v for v in versions if v >= Version(bound) and not v.is_prerelease]
    if not ok:
        raise SystemExit(f"{name}: no release at or above {bound}")
    return str(min(ok))


if __name__ == "__main__":
    for name, bound in sorted(lower_bounds().items()):
        print(f"{name}=={oldest_release(name, bound)}")
