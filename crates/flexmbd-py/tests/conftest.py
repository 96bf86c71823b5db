"""Shared fixtures of the Python tests: the repository's examples and the `flexmbd` binary
that `cargo test`/`cargo build` made (FLEXMBD overrides it)."""

import os
import pathlib
import subprocess

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[3]
EXAMPLES = sorted((ROOT / "examples").glob("*.toml"))


def flexmbd_binary():
    env = os.environ.get("FLEXMBD")
    if env:
        return env
    target = os.environ.get("CARGO_TARGET_DIR", str(ROOT / "target"))
    return str(pathlib.Path(target) / "debug" / "flexmbd")


@pytest.fixture(scope="session")
def cli():
    """Run `flexmbd ARGS --json` in the repository root: (exit code, parsed JSON or None,
    stderr)."""
    import json

    exe = flexmbd_binary()
    if not os.path.exists(exe):
        pytest.fail(f"the flexmbd binary {exe} is missing: run `cargo build -p flexmbd-cli` first (or set FLEXMBD)")

    def run(*args):
        p = subprocess.run(
            [exe, "--quiet", *args, "--json"], cwd=ROOT, capture_output=True, text=True
        )
        doc = json.loads(p.stdout) if p.stdout.strip() else None
        return p.returncode, doc, p.stderr

    return run


@pytest.fixture(autouse=True)
def in_root(monkeypatch):
    """Every test runs in the repository root, so relative example paths match the CLI's."""
    monkeypatch.chdir(ROOT)
