#!/usr/bin/env bash
# glview's Python API beside pyrender (python/bench/bench_vs_pyrender.py): makes the glview
# venv as scripts/test_python.sh does and a pyrender venv (numpy<2, PyOpenGL on EGL), then
# prints one table. A benchmark, not a test: CI does not run it.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/deps.sh
[ -x target/pyvenv/bin/python ] || python3 -m venv target/pyvenv
target/pyvenv/bin/pip install --quiet maturin numpy
CARGO_TARGET_DIR="$PWD/target" target/pyvenv/bin/pip install --quiet --force-reinstall --no-deps ./python
[ -x target/pyrender-venv/bin/python ] || python3 -m venv target/pyrender-venv
target/pyrender-venv/bin/pip install --quiet pyrender "numpy<2" trimesh
target/pyvenv/bin/python python/bench/bench_vs_pyrender.py
