#!/usr/bin/env bash
# The crate is ready to publish:
#  - the library and the CLI build with the `rust-version` in Cargo.toml (the
#    MSRV, installed here with rustup if missing) and the committed Cargo.lock;
#  - `cargo publish --dry-run` passes: it packages the crate (the `include`
#    list in Cargo.toml), builds the packaged copy on its own (so a file the
#    build needs but the package lacks fails here) and stops before the
#    upload. No crates.io token is needed.
# Run from scripts/test-all.sh; works on its own too.
set -euo pipefail
cd "$(dirname "$0")/.."

msrv=$(sed -n 's/^rust-version = "\([0-9.]*\)".*/\1/p' Cargo.toml)
if [ -z "$msrv" ]; then
    echo "check-package: no rust-version = \"...\" line in Cargo.toml" >&2
    exit 1
fi

echo "MSRV $msrv: library and CLI, all features"
rustup --quiet toolchain install "$msrv" --profile minimal --no-self-update >/dev/null
cargo "+$msrv" check --quiet --locked --all-features --lib --bins

# A clean clone packages as it is; uncommitted changes (a local run while
# editing) are packaged too, with a note, rather than failing the run.
dirty=()
if [ -n "$(git status --porcelain 2>/dev/null)" ]; then
    echo "(uncommitted changes: packaging the working tree, --allow-dirty)"
    dirty=(--allow-dirty)
fi

# Cargo prints the file count and the .crate size ("Packaged ..."), and warns
# that tests/firmware_checksum.rs is left out (it reads targets/, which stays
# in the repository).
echo "cargo publish --dry-run: package, build the packaged crate"
cargo publish --dry-run --locked "${dirty[@]}"
