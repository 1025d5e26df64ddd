"""Shared helpers of the Python tests: where the CLI and the sources are, and how to insist on
external tools. CTest sets FMCW_CLI and FMCW_SOURCE_DIR (tests/python/CMakeLists.txt)."""

import importlib
import os
import shutil
import subprocess
from pathlib import Path

import pytest

SOURCE_DIR = Path(os.environ.get("FMCW_SOURCE_DIR", Path(__file__).resolve().parents[2]))


def cli_path():
    cli = os.environ.get("FMCW_CLI")
    if not cli or not Path(cli).exists():
        pytest.fail("FMCW_CLI does not name the built fmcw CLI (run these tests through ctest)")
    return cli


def run_cli(*args, expect_ok=True):
    """Runs `fmcw ARGS`; returns the CompletedProcess. Fails the test on a non-zero exit when expect_ok."""
    proc = subprocess.run([cli_path(), *map(str, args)], capture_output=True, text=True, timeout=600)
    if expect_ok and proc.returncode != 0:
        pytest.fail(f"fmcw {' '.join(map(str, args))} exited {proc.returncode}:\n{proc.stderr}")
    return proc


def _missing(what, package):
    """A missing external tool skips the test, unless FMCW_REQUIRE_EXTERNAL_TOOLS=1 (set by
    scripts/test_all.sh, after scripts/setup.sh installed the tools): then it fails, so that CI
    cannot pass by skipping the checks."""
    message = f"{what} is not installed (Debian package {package}; scripts/setup.sh installs it)"
    if os.environ.get("FMCW_REQUIRE_EXTERNAL_TOOLS") == "1":
        pytest.fail(message + ", and FMCW_REQUIRE_EXTERNAL_TOOLS=1 requires it")
    pytest.skip(message)


def require_module(name, package):
    try:
        return importlib.import_module(name)
    except ImportError:
        _missing(f"Python module {name}", package)


def require_program(name, package):
    path = shutil.which(name)
    if path is None:
        _missing(f"program {name}", package)
    return path
