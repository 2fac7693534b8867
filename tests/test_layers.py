"""The layers import only downwards (README, Layout): physics knows nothing of rules or the
server; rules nothing of the server; the protocol nothing of the game service or HTTP; the
game service nothing of HTTP or the clients; the clients nothing but the protocol; the relay
nothing of billiards. Read from the source, so a new import that crosses a layer fails here."""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]

#: Each package and the project packages it must never import (prefixes of module names).
FORBIDDEN = {
    "physics": ("rules", "server"),
    "rules": ("server",),
    "server/relay": ("server.game", "server.http", "server.protocol", "server.client", "rules"),
    "server/protocol": ("server.game", "server.http", "server.storage", "server.client"),
    "server/storage": ("server.http", "server.client"),
    "server/game": ("server.http", "server.client"),
    "server/client": ("server.game", "server.http", "server.storage", "server.relay"),
}


def imported(path: Path) -> set[str]:
    """Every module a file imports, at any depth of its code."""
    names: set[str] = set()
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.Import):
            names.update(alias.name for alias in node.names)
        elif isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
            names.add(node.module)
            names.update(f"{node.module}.{alias.name}" for alias in node.names)
    return names


@pytest.mark.parametrize("package", sorted(FORBIDDEN))
def test_a_layer_imports_nothing_above_it(package: str) -> None:
    crossings = [
        f"{path.relative_to(ROOT)} imports {name}"
        for path in sorted((ROOT / package).rglob("*.py"))
        for name in sorted(imported(path))
        if any(name == banned or name.startswith(banned + ".") for banned in FORBIDDEN[package])
    ]
    assert crossings == []
