#!/usr/bin/env bash
# All of flexmbd's tests: the Rust workspace (`cargo test --workspace`), then the Python
# package: its wheel built by maturin and installed by pip into a virtual environment (PyPI
# only), and its pytest suite (crates/flexmbd-py/tests/), which compares the package's results
# with those of the `flexmbd` binary that `cargo test` built.
#
# FLEXMBD_PY_VENV: the virtual environment (default ~/.cache/flexmbd-py-venv; made if missing).
set -euo pipefail
cd "$(dirname "$0")"

cargo test --workspace

VENV="${FLEXMBD_PY_VENV:-$HOME/.cache/flexmbd-py-venv}"
if [ ! -x "$VENV/bin/python" ]; then
  python3 -m venv "$VENV"
fi
PY="$VENV/bin/python"
"$PY" -m pip install --quiet --disable-pip-version-check pytest numpy control matplotlib "dask[distributed]"
# the README's install command, into the venv (maturin comes from PyPI as the build backend)
# (--force-reinstall: the same version number, rebuilt from the current source)
"$PY" -m pip install --quiet --disable-pip-version-check --force-reinstall --no-deps ./crates/flexmbd-py
FLEXMBD="${CARGO_TARGET_DIR:-$PWD/target}/debug/flexmbd" "$PY" -m pytest -q crates/flexmbd-py/tests
