#!/usr/bin/env bash
# The one test command: every Rust test, then the Python package's tests.
#
# On a machine with only Rust (stable) and Python ≥ 3.11: makes a venv in .venv (or
# $OPALRAY_VENV), builds the abi3 wheel (`maturin build`) and installs it with its test
# extras (pytest, numpy, dask[distributed]), runs `cargo test --workspace`, then pytest. Scratch
# files of pytest and Dask stay under one temporary folder, removed at the end.
set -euo pipefail
cd "$(dirname "$0")/.."
root="$PWD"

venv="${OPALRAY_VENV:-.venv}"
python="${PYTHON:-python3}"
if [ ! -x "$venv/bin/python" ]; then
    "$python" -m venv "$venv"
fi
"$venv/bin/python" -m pip install --quiet "maturin>=1.7,<2"

scratch="$(mktemp -d "${TMPDIR:-/tmp}/opalray-test.XXXXXX")"
trap 'rm -rf "$scratch"' EXIT

# The abi3 wheel that people without Rust install, built in release mode (as the CLI's binary
# the tests compare with); the tests run against it, installed with its test extras.
"$venv/bin/maturin" build --release --quiet --out "$scratch/wheels"
wheels=("$scratch"/wheels/opalray-*-abi3-*.whl)
if [ "${#wheels[@]}" -ne 1 ] || [ ! -f "${wheels[0]}" ]; then
    echo "maturin build: expected one abi3 wheel in $scratch/wheels" >&2
    exit 1
fi
"$venv/bin/python" -m pip install --quiet --force-reinstall --no-deps "${wheels[0]}"
"$venv/bin/python" -m pip install --quiet "${wheels[0]}[test]"
echo "test.sh: the wheel built and installed, $SECONDS s"

cargo test --workspace
echo "test.sh: the Rust tests passed, $SECONDS s"
# The tests compare the Python renders with the release binary's.
cargo build --release -p opalray-cli
export OPALRAY_BIN="$root/target/release/opalray"

export DASK_TEMPORARY_DIRECTORY="$scratch/dask"
# Run from the scratch folder so that `import opalray` is the installed package, not python/.
venv_python="$(cd "$venv" && pwd)/bin/python"
# The ten slowest tests are named at the end (`--durations`), for whoever trims the run.
(cd "$scratch" && "$venv_python" -m pytest -p no:cacheprovider --basetemp="$scratch/pytest" \
    --durations=10 "$root/python/tests" "$@")
