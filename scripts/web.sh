#!/usr/bin/env bash
# The browser preview (web/): raypack's no_std core in WebAssembly SIMD, a
# static page and its Web Worker.
#
#   ./scripts/web.sh          # build web/dist (the page, the .wasm, the SPD scenes)
#   ./scripts/web.sh serve    # build, then serve web/dist at http://127.0.0.1:8000/ (PORT=... to change)
#   ./scripts/web.sh test     # build, then the real-browser test (headless Debian chromium)
#   ./scripts/web.sh bench    # build, then packet 4 vs 1 in the browser, interleaved (docs/web.md)
#
# Installs what it needs on a fresh Debian machine: the rustup target
# wasm32-unknown-unknown, Debian's binaryen (wasm-opt, which shrinks the
# module), and for `test`/`bench` Debian's chromium and wabt (wasm-objdump,
# for the panic-path check). Nothing else is downloaded.
set -euo pipefail
cd "$(dirname "$0")/.."

say() { printf '\n== %s\n' "$*"; }
die() { printf 'web.sh: error: %s\n' "$*" >&2; exit 1; }

MODE=${1:-build}
DIST=web/dist
WASM_OUT=web/target/wasm32-unknown-unknown/release/raypack_web.wasm
WASM_OPT=web/target/raypack_web.opt.wasm
# The .wasm budget (1 KB = 1000 bytes).
MAX_KB=${RAYPACK_WASM_MAX_KB:-200}

apt_install() { # PACKAGE COMMAND: installs PACKAGE unless COMMAND exists
  command -v "$2" >/dev/null && return 0
  command -v apt-get >/dev/null || die "$2 is missing and there is no apt-get to install $1"
  say "installing $1 (Debian)"
  local sudo=""
  [ "$(id -u)" = 0 ] || sudo=sudo
  $sudo apt-get update -qq >/dev/null || true
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq "$1" >/dev/null || die "apt-get install $1 failed"
  command -v "$2" >/dev/null || die "$1 installed but $2 is still missing"
}

build() {
  say "rustup target wasm32-unknown-unknown"
  rustup target add wasm32-unknown-unknown >/dev/null
  say "web: cargo build --release --target wasm32-unknown-unknown (+simd128)"
  (cd web && cargo build --release --locked --target wasm32-unknown-unknown)
  apt_install binaryen wasm-opt
  say "web: wasm-opt -Oz ($(wasm-opt --version))"
  wasm-opt -Oz "$WASM_OUT" -o "$WASM_OPT"
  say "web: assemble $DIST"
  rm -rf "$DIST"
  mkdir -p "$DIST/scenes"
  cp web/index.html web/app.js web/worker.js "$DIST/"
  cp tests/scenes/*.nff "$DIST/scenes/"
  python3 - "$DIST/scenes" <<'PY'
import json, os, sys
d = sys.argv[1]
names = sorted(f[:-4] for f in os.listdir(d) if f.endswith(".nff"))
open(os.path.join(d, "index.json"), "w").write(json.dumps(names) + "\n")
PY
  # The module without its custom sections (names, producers): what the page
  # loads. Panic paths are traced in the module as rustc linked it (with its
  # names; wasm-opt only removes and rewrites code).
  python3 web/test/check_module.py "$WASM_OPT" --strip-to "$DIST/raypack_web.wasm" --max-kb "$MAX_KB" \
    ${CHECK_ARGS:+$CHECK_ARGS --panic-from "$WASM_OUT"}
}

cli() { # the host raypack command line (debug build, the features `cargo test --all-features` built it with)
  cargo build -q --all-features --bin raypack >&2
  echo "target/debug/raypack"
}

case "$MODE" in
  build)
    build
    ;;
  serve)
    build
    PORT=${PORT:-8000}
    say "serving $DIST at http://127.0.0.1:$PORT/ (Ctrl-C to stop)"
    exec python3 -m http.server --bind 127.0.0.1 --directory "$DIST" "$PORT"
    ;;
  test)
    apt_install wabt wasm-objdump
    CHECK_ARGS=--panic-paths build
    say "web: host unit tests of the preview's state machine (cargo test)"
    (cd web && cargo test -q --locked)
    apt_install chromium chromium
    say "host CLI (for the host's checksums and error lines)"
    RAYPACK_CLI=$(cli)
    say "browser test: headless chromium, page from 127.0.0.1"
    python3 web/test/browser_test.py --dist "$DIST" --raypack "$RAYPACK_CLI" --chromium "$(command -v chromium)"
    ;;
  bench)
    build
    apt_install chromium chromium
    say "browser bench: packet 4 vs 1, interleaved"
    python3 web/test/browser_test.py --dist "$DIST" --chromium "$(command -v chromium)" --bench "${@:2}"
    ;;
  *)
    die "unknown mode $MODE (build, serve, test, bench)"
    ;;
esac
