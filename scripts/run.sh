#!/usr/bin/env bash
# Runs glview on the built-in scene (or the arguments given): a window when there is a
# display, otherwise a PNG (glview.png) rendered headless.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/deps.sh
exec cargo run --release --quiet --bin glview -- "$@"
