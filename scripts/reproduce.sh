#!/usr/bin/env bash
# Sets up, builds and runs `slamcmp reproduce`: renders tv1..tv4 and compares every back-end on
# them. The report lands in out/reproduce/report.md. Extra arguments go to reproduce.
set -euo pipefail
cd "$(dirname "$0")/.."
./scripts/build.sh
./build/eval/slamcmp reproduce --out out/reproduce "$@"
