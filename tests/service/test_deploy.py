"""The deployment files, checked without a Docker engine (none runs here, and the Docker CLI
has no `compose` plugin): docker-compose.yml, deploy/Dockerfile and deploy/nginx.conf are
parsed and their references checked against the tree and against the server's own CLI."""

from __future__ import annotations

import fnmatch
import ipaddress
import re
import shlex
from pathlib import Path

import pytest
import yaml

from server.cli import build_parser

ROOT = Path(__file__).resolve().parents[2]
COMPOSE = yaml.safe_load((ROOT / "docker-compose.yml").read_text())
SERVICES = COMPOSE["services"]
REPLICAS = [name for name, service in SERVICES.items() if "build" in service]


def dockerfile_instructions(path: Path) -> list[tuple[str, str]]:
    """(INSTRUCTION, arguments) of a Dockerfile, continuation lines joined, comments dropped."""
    text = re.sub(r"\\\n", " ", path.read_text())
    lines = [line.strip() for line in text.splitlines()]
    return [
        (line.split(None, 1)[0].upper(), line.split(None, 1)[1] if " " in line else "")
        for line in lines
        if line and not line.startswith("#")
    ]


def ignored(path: str, patterns: list[str]) -> bool:
    """Whether a context path is left out by .dockerignore-style `patterns` (no negations)."""
    parts = path.strip("/").split("/")
    prefixes = ["/".join(parts[: i + 1]) for i in range(len(parts))]
    for pattern in patterns:
        pattern = pattern.strip("/").removeprefix("**/")
        if any(
            fnmatch.fnmatch(p, pattern) or fnmatch.fnmatch(p.split("/")[-1], pattern)
            for p in prefixes
        ):
            return True
    return False


def serve_args(service: dict) -> object:
    """The replica's command parsed by the real `billiards` parser."""
    command = service["command"]
    assert command[0] == "billiards"
    args = build_parser().parse_args(command[1:])
    assert args.command == "serve"
    return args


def nginx_upstreams(text: str) -> dict[str, list[str]]:
    blocks = re.findall(r"upstream\s+(\w+)\s*\{([^}]*)\}", text)
    return {name: re.findall(r"^\s*server\s+(\S+)", body, re.M) for name, body in blocks}


def test_every_copy_source_exists_in_the_build_context_and_is_not_ignored():
    build = SERVICES[REPLICAS[0]]["build"]
    context = ROOT / build["context"]
    dockerfile = ROOT / build["dockerfile"]
    ignore = (dockerfile.parent / f"{dockerfile.name}.dockerignore").read_text().splitlines()
    ignore = [p for p in ignore if p.strip() and not p.startswith("#")]
    stages: set[str] = set()
    copies = 0
    for instruction, arguments in dockerfile_instructions(dockerfile):
        if instruction == "FROM" and " AS " in arguments.upper():
            stages.add(arguments.split()[-1])
        if instruction != "COPY":
            continue
        words = shlex.split(arguments)
        flags = [w for w in words if w.startswith("--")]
        sources = [w for w in words if not w.startswith("--")][:-1]
        source_stage = next((f.split("=", 1)[1] for f in flags if f.startswith("--from=")), None)
        if source_stage is not None:
            assert source_stage in stages, f"COPY --from={source_stage}: no such stage"
            continue
        for source in sources:
            copies += 1
            assert (context / source).exists(), f"COPY {source}: not in the build context"
            if source != ".":
                assert not ignored(source, ignore), f"COPY {source}: left out by dockerignore"
    assert copies >= 3
    # What the image runs: the package, its console script, and the web client built into it.
    assert not ignored("server/http/app.py", ignore) and not ignored("pyproject.toml", ignore)
    assert "web/dist" in dockerfile.read_text()


def test_redis_persists_every_write_to_a_volume():
    redis = SERVICES["redis"]
    command = redis["command"]
    assert command[0] == "redis-server"
    assert command[command.index("--appendonly") + 1] == "yes"
    volume = redis["volumes"][0]
    assert volume.split(":")[1] == "/data" and volume.split(":")[0] in COMPOSE["volumes"]


def test_three_replicas_serve_on_one_port_with_the_shared_redis_and_secret():
    assert len(REPLICAS) == 3
    ports = set()
    for name in REPLICAS:
        service = SERVICES[name]
        args = serve_args(service)
        assert args.host == "0.0.0.0"
        ports.add(args.port)
        host = re.match(r"redis://([^:/]+):(\d+)", args.redis)
        assert host and host.group(1) in SERVICES and host.group(2) == "6379"
        assert "BILLIARDS_RELAY_SECRET" in service["environment"]  # one token key for all
        assert "redis" in service["depends_on"]
    assert len(ports) == 1
    exposed = [a for i, a in dockerfile_instructions(ROOT / "deploy/Dockerfile") if i == "EXPOSE"]
    assert exposed == [str(ports.pop())]


def test_replicas_trust_the_compose_network_for_forwarded_addresses():
    """nginx reaches the replicas from the compose network's subnet: that is the proxy whose
    X-Forwarded-For the replicas believe, and each player's address is then bounded."""
    (subnet,) = [c["subnet"] for c in COMPOSE["networks"]["default"]["ipam"]["config"]]
    for name in REPLICAS:
        args = serve_args(SERVICES[name])
        assert [ipaddress.ip_network(p) for p in args.trusted_proxy] == [
            ipaddress.ip_network(subnet)
        ]
        assert args.max_connections_per_address and args.max_connections_per_address >= 16


def test_nginx_balances_every_replica_and_passes_websocket_upgrades():
    lb = next(s for s in SERVICES.values() if str(s.get("image", "")).startswith("nginx"))
    source, target = lb["volumes"][0].split(":")[:2]
    conf_path = ROOT / source
    assert conf_path.is_file() and target == "/etc/nginx/nginx.conf"
    conf = conf_path.read_text()
    upstreams = nginx_upstreams(conf)
    for proxied in re.findall(r"proxy_pass\s+http://([\w.-]+)", conf):
        assert proxied in upstreams, f"proxy_pass to {proxied}: no such upstream"
    port = serve_args(SERVICES[REPLICAS[0]]).port
    (servers,) = upstreams.values()
    assert sorted(servers) == sorted(f"{name}:{port}" for name in REPLICAS)
    assert re.search(r"proxy_http_version\s+1\.1;", conf)
    assert re.search(r"proxy_set_header\s+Upgrade\s+\$http_upgrade;", conf)
    assert re.search(r"proxy_set_header\s+Connection\s+\$connection_upgrade;", conf)
    assert re.search(r"map\s+\$http_upgrade\s+\$connection_upgrade", conf)
    assert re.search(r"proxy_buffering\s+off;", conf)  # SSE and long-poll stream through
    listen = re.search(r"listen\s+(\d+);", conf)
    assert listen and lb["ports"] == [f"8080:{listen.group(1)}"]
    assert set(lb["depends_on"]) == set(REPLICAS)


@pytest.mark.parametrize("path", ["web/package.json", "web/package-lock.json", "web/build.mjs"])
def test_the_web_build_stage_has_its_inputs(path):
    assert (ROOT / path).is_file()
