#!/usr/bin/env bash
# Runs every raypack test. Works on a fresh Debian machine with rustup:
# installs the rustup targets (and, once firmware exists, QEMU) it needs.
# A missing tool is a failure with a clear message, never a silent skip.
set -euo pipefail
cd "$(dirname "$0")/.."

say() { printf '\n== %s\n' "$*"; }

say "rustup targets"
rustup target add thumbv7em-none-eabihf >/dev/null

say "module graph: no cycles (scripts/module-graph.py)"
python3 scripts/module-graph.py --quiet

say "formatting (cargo fmt --check) and lints (cargo clippy, -D warnings; allow list in Cargo.toml)"
rustup component add rustfmt clippy >/dev/null
cargo fmt --check
cargo clippy --all-targets --all-features -q -- -D warnings

say "cargo test (host, all features)"
cargo test --all-features

say "core builds for bare metal (no_std, no alloc)"
cargo build --lib --no-default-features --target thumbv7em-none-eabihf
cargo build --lib --no-default-features --features embedded-graphics --target thumbv7em-none-eabihf

say "docs build without warnings"
RUSTDOCFLAGS="-D warnings" cargo doc --no-deps --all-features -q

say "dispatched machine code: packed, no FMA (x86-64)"
./scripts/check-asm.sh

say "crate: MSRV builds, package builds, publish dry run (scripts/check-package.sh)"
./scripts/check-package.sh

say "firmware: build, prove panic-free, run under QEMU, compare with the host"
./scripts/firmware.sh

say "browser preview: wasm32 + simd128 build, module checks, headless chromium test (scripts/web.sh test)"
# The module is about 200 KB (docs/web.md has the figure and says
# where the code goes): the budget here only keeps it from growing.
RAYPACK_WASM_MAX_KB=200 ./scripts/web.sh test

say "all tests passed"
