#!/usr/bin/env bash
# Re-resolve requirements.in into the hash-pinned requirements.lock (needs uv: pip install uv).
set -euo pipefail
cd "$(dirname "$0")/.."
uv pip compile requirements.in --generate-hashes --python-version 3.11 \
  --python-platform x86_64-manylinux_2_28 -o requirements.lock "$@"
