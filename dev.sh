#!/usr/bin/env bash
# One entry point for a fresh machine: `bash dev.sh serve` or `bash dev.sh test`.
# Each command installs what it needs first (idempotently) and then runs.
set -euo pipefail
cd "$(dirname "$0")"
VENV=.venv
PY=${PYTHON:-python3}

setup_python() {
    if [ ! -x "$VENV/bin/python" ]; then
        "$PY" -m venv "$VENV"
    fi
    # Reinstall only when pyproject.toml changed since the last install.
    local stamp="$VENV/.installed-$(sha1sum pyproject.toml | cut -c1-12)"
    if [ ! -f "$stamp" ]; then
        "$VENV/bin/pip" install --quiet --upgrade pip
        # The diagrams and fit extras too: the tests draw the figures and fit recorded shots.
        "$VENV/bin/pip" install --quiet -e ".[test,diagrams,fit]"
        rm -f "$VENV"/.installed-*
        touch "$stamp"
    fi
    # The compiled kernel (setup.py), rebuilt in place when its sources changed since: else
    # the extension modules built from the old source would shadow the edited .py files.
    "$VENV/bin/python" setup.py -q build_ext --inplace >"$VENV/kernel-build.log" 2>&1 || true
}

require_kernel() {  # the tests compare the two paths: the kernel must have been built
    if ! "$VENV/bin/python" -c 'from physics import kernel; assert kernel.compiled()' 2>/dev/null; then
        cat "$VENV/kernel-build.log" >&2
        echo "dev.sh: the compiled kernel did not build (the build's messages are above)" >&2
        exit 1
    fi
}

need_debian_package() {  # need_debian_package BINARY PACKAGE
    if ! command -v "$1" >/dev/null 2>&1; then
        if [ "$(id -u)" = 0 ]; then
            apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq "$2"
        else
            echo "dev.sh: '$1' is missing; install the Debian package '$2'" >&2
            exit 1
        fi
    fi
}

setup_web() {
    need_debian_package npm npm
    # npm ci only when the lock file changed since the last install; the build always (< 1 s).
    local stamp="web/node_modules/.installed-$(sha1sum web/package-lock.json | cut -c1-12)"
    if [ ! -f "$stamp" ]; then
        (cd web && npm ci --ignore-scripts --no-audit --no-fund --loglevel=error)
        touch "$stamp"
    fi
    (cd web && npm run --silent build)
}

case "${1:-}" in
    serve)
        setup_python
        setup_web
        shift
        exec "$VENV/bin/billiards" serve "$@"
        ;;
    test)
        need_debian_package gcc gcc
        setup_python
        require_kernel
        need_debian_package redis-server redis-server
        need_debian_package nginx nginx  # tests/service/test_topology.py: the load balancer
        need_debian_package chromium chromium
        setup_web
        shift
        "$VENV/bin/ruff" check .
        "$VENV/bin/ruff" format --check .
        if [ $# -gt 0 ]; then
            exec "$VENV/bin/pytest" -q "$@"
        fi
        # The whole suite on the compiled kernel, then the physics suites on the pure-Python
        # engine (docs/physics.md, "The compiled kernel"); tests/physics_kernel compares the two.
        echo "dev.sh: the whole suite, compiled kernel"
        "$VENV/bin/pytest" -q
        echo "dev.sh: the physics suites, pure-Python engine (BILLIARDS_PURE_PYTHON=1)"
        BILLIARDS_PURE_PYTHON=1 exec "$VENV/bin/pytest" -q \
            tests/physics tests/physics_models tests/accuracy tests/physics_kernel
        ;;
    *)
        echo "usage: bash dev.sh serve [--host H] [--port P] | bash dev.sh test [pytest args]" >&2
        exit 2
        ;;
esac
