#!/usr/bin/env bash
# Builds every raypack firmware under targets/, proves it panic-free, runs it
# under QEMU and compares the checksums it prints with the host's.
#
#   ./scripts/firmware.sh            # everything (what test-all.sh runs)
#
# Installs what it needs on a fresh Debian machine (rustup targets,
# llvm-tools, QEMU's Arm and RISC-V system emulators) and fails loudly when
# something is missing or any board disagrees with the host. Idempotent.
#
# QEMU: Debian bookworm's qemu-system-arm/-misc (7.2). When apt cannot install
# them beside what the machine has (this kind of machine ships qemu-utils from
# bookworm-backports, which Breaks qemu-system-common 7.2), the two emulator
# binaries are unpacked from the same Debian packages into
# ${RAYPACK_QEMU_DIR:-~/.cache/raypack-qemu} and their libraries installed by
# apt; nothing already installed is removed or downgraded.
set -euo pipefail
cd "$(dirname "$0")/.."
ROOT=$PWD

say() { printf '\n== %s\n' "$*"; }
die() { printf '\nFIRMWARE FAILURE: %s\n' "$*" >&2; exit 1; }

# board  target-triple  packet-width  scalars  qemu command (ELF appended)
BOARDS=(
  "mps2-an386|thumbv7em-none-eabihf|8|f32|qemu-system-arm -cpu cortex-m4 -M mps2-an386 -nographic -semihosting-config enable=on,target=native -kernel"
  "microbit|thumbv6m-none-eabi|1|f32,fixed|qemu-system-arm -cpu cortex-m0 -M microbit -nographic -semihosting-config enable=on,target=native -kernel"
  "riscv-virt|riscv32imac-unknown-none-elf|4|f32,fixed|qemu-system-riscv32 -M virt -bios none -nographic -semihosting -kernel"
)
QEMU_TIMEOUT=${RAYPACK_QEMU_TIMEOUT:-300}

# ---------------------------------------------------------------- tools
say "rustup targets and llvm-tools"
rustup target add thumbv7em-none-eabihf thumbv6m-none-eabi riscv32imac-unknown-none-elf >/dev/null
rustup component add llvm-tools >/dev/null
HOST_TRIPLE=$(rustc -vV | sed -n 's/^host: //p')
LLVM_SIZE="$(rustc --print sysroot)/lib/rustlib/$HOST_TRIPLE/bin/llvm-size"
[ -x "$LLVM_SIZE" ] || die "llvm-size not found at $LLVM_SIZE (rustup component add llvm-tools)"

QEMU_DIR=${RAYPACK_QEMU_DIR:-$HOME/.cache/raypack-qemu}
QEMU_PREFIX=
qemu_works() { # $1: prefix ("" for PATH)
  "${1}qemu-system-arm" --version >/dev/null 2>&1 && "${1}qemu-system-riscv32" --version >/dev/null 2>&1
}
find_qemu() {
  if qemu_works ""; then QEMU_PREFIX=""; return 0; fi
  if qemu_works "$QEMU_DIR/usr/bin/"; then QEMU_PREFIX="$QEMU_DIR/usr/bin/"; return 0; fi
  return 1
}
install_qemu() {
  command -v apt-get >/dev/null || die "QEMU missing and no apt-get: install qemu-system-arm and qemu-system-misc (qemu-system-riscv32)"
  [ "$(id -u)" = 0 ] || die "QEMU missing: run as root, or install qemu-system-arm and qemu-system-misc"
  local apt=(apt-get -y -q -o DPkg::Lock::Timeout=600)
  "${apt[@]}" update >/dev/null || die "apt-get update failed"
  # The plain way; --no-remove: never take away what the machine has.
  if "${apt[@]}" install --no-install-recommends --no-remove qemu-system-arm qemu-system-misc >/tmp/raypack-qemu-apt.log 2>&1; then
    return 0
  fi
  echo "apt cannot install qemu-system-* beside the installed packages (see /tmp/raypack-qemu-apt.log);"
  echo "unpacking the emulators from the Debian packages into $QEMU_DIR"
  local deps
  deps=$(apt-cache depends --no-recommends --no-suggests --no-conflicts --no-breaks --no-replaces --no-enhances \
           qemu-system-arm qemu-system-misc | awk '$1 == "Depends:" { print $2 }' | grep -v '^qemu-' | grep -v '^<' | sort -u)
  # shellcheck disable=SC2086
  "${apt[@]}" install --no-install-recommends --no-remove $deps >/dev/null || die "could not install QEMU's libraries: $deps"
  local tmp
  tmp=$(mktemp -d)
  chmod 755 "$tmp"
  (cd "$tmp" && apt-get download -q qemu-system-arm qemu-system-misc >/dev/null 2>&1) || die "apt-get download qemu-system-arm qemu-system-misc failed"
  mkdir -p "$QEMU_DIR"
  for deb in "$tmp"/qemu-system-arm_*.deb "$tmp"/qemu-system-misc_*.deb; do
    [ -f "$deb" ] || die "downloaded package missing: $deb"
    dpkg-deb --fsys-tarfile "$deb" | tar -x -C "$QEMU_DIR" ./usr/bin/qemu-system-arm ./usr/bin/qemu-system-riscv32 2>/dev/null || true
  done
  rm -rf "$tmp"
}
say "QEMU"
if ! find_qemu; then
  install_qemu
  find_qemu || die "QEMU still not runnable after installing (qemu-system-arm / qemu-system-riscv32)"
fi
"${QEMU_PREFIX}qemu-system-arm" --version | head -1
echo "(${QEMU_PREFIX:-from PATH}qemu-system-arm, qemu-system-riscv32)"

# ---------------------------------------------------------------- host
say "host checksums (same core, same scene)"
RECORDED=$(grep -v '^#' targets/checksums.txt | sed '/^[[:space:]]*$/d')
HOST=$(cargo run -q --example firmware_checksum)
echo "$HOST"
if [ "$HOST" != "$RECORDED" ]; then
  printf 'host:\n%s\nrecorded (targets/checksums.txt):\n%s\n' "$HOST" "$RECORDED" >&2
  die "the host's checksums differ from targets/checksums.txt"
fi

cd targets
say "firmware support crate: host unit tests"
cargo test -q -p raypack-firmware-common --lib

# ---------------------------------------------------------------- boards
SUMMARY=()
for entry in "${BOARDS[@]}"; do
  IFS='|' read -r board triple width scalars qemu <<<"$entry"
  elf="target/$triple/release/raypack-$board"

  say "$board: build (release, LTO)"
  cargo build -q --release -p "raypack-$board" --target "$triple" || die "$board: build failed"

  say "$board: sizes"
  "$LLVM_SIZE" -A "$elf" | grep -E '^(section|\.vector_table|\.text|\.rodata|\.data|\.bss|\.uninit|\.init)' || true
  sec() { "$LLVM_SIZE" -A "$elf" | awk -v s="$1" '$1 == s { print $2; f = 1 } END { if (!f) print 0 }'; }
  text=$(( $(sec .text) + $(sec .init) + $(sec .vector_table) ))
  rodata=$(sec .rodata)
  dataplusbss=$(( $(sec .data) + $(sec .bss) + $(sec .uninit) ))

  say "$board: run under QEMU ($QEMU_TIMEOUT s limit)"
  read -r -a qcmd <<<"$qemu"
  qcmd[0]="${QEMU_PREFIX}${qcmd[0]}"
  start=$(date +%s%N)
  set +e
  out=$(timeout -k 10 "$QEMU_TIMEOUT" "${qcmd[@]}" "$elf" 2>&1 </dev/null)
  rc=$?
  set -e
  wall=$(( ($(date +%s%N) - start) / 1000000 ))
  echo "$out"
  [ $rc -ne 124 ] || die "$board: QEMU timed out after $QEMU_TIMEOUT s"
  [ $rc -eq 0 ] || die "$board: firmware exited with status $rc"
  grep -q '^result=ok$' <<<"$out" || die "$board: firmware did not report result=ok"

  match=yes
  for scalar in ${scalars//,/ }; do
    while read -r s key value; do
      [ "$s" = "$scalar" ] || continue
      if ! grep -qE "^${s}\.${key}=${value}( |\$)" <<<"$out"; then
        echo "MISMATCH on $board: host says '$s $key $value'" >&2
        match=NO
      fi
    done <<<"$HOST"
  done
  [ $match = yes ] || die "$board: checksum differs from the host's"

  # After the run: the release panic-never build replaces the binary run above.
  say "$board: no reachable panic (panic-never link, release + LTO)"
  cargo build -q --release -p "raypack-$board" --target "$triple" --features panic-never \
    || die "$board: a panic is reachable (the panic-never build did not link)"
  # Stricter, opt-in: overflow checks on as well (passed for every board
  # before the BVH merge; not yet re-proved with the BVH traversal).
  if [ "${RAYPACK_OVERFLOW_PROOF:-0}" = 1 ]; then
    say "$board: no reachable panic with overflow checks on (profile panic-never)"
    cargo build -q --profile panic-never -p "raypack-$board" --target "$triple" --features panic-never \
      || die "$board: a panic (or integer overflow) is reachable with overflow checks on"
  fi

  stack=$(sed -n 's/^stack-high-water=\([0-9]*\).*/\1/p' <<<"$out")
  sram=$(sed -n 's/^static-ram=\([0-9]*\).*/\1/p' <<<"$out")
  SUMMARY+=("| $board | ${scalars} | $width | $text | $rodata | $dataplusbss ($sram) | $stack | $(printf '%d.%03d' $((wall / 1000)) $((wall % 1000))) s | $match |")
done

say "summary (sizes in bytes; static RAM from llvm-size, in parentheses as measured on the chip)"
echo "| board | scalar | width | .text | .rodata | .data+.bss | stack high-water | QEMU wall time | checksum = host |"
echo "| --- | --- | --- | --- | --- | --- | --- | --- | --- |"
printf '%s\n' "${SUMMARY[@]}"
say "firmware: all boards match the host"
