#!/usr/bin/env bash
# Builds every raypack firmware under targets/, proves it panic-free, runs it
# under QEMU (virtual time = instructions: -icount shift=0), checks that every
# run is deterministic, compares the checksums it prints with the host's, and
# prints sizes and instruction counts per frame, pixel and ray. Also builds
# the Raspberry Pi Pico display firmware (no QEMU machine: built and proved
# panic-free, not run) and a downstream crate resolved afresh beside mipidsi.
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

# Instruction counting: QEMU's virtual clock advances exactly 1 ns per guest
# instruction (2^0), no alignment of virtual to real time, and no sleeping
# when the guest idles (it never does while measuring). The firmware reads a
# timer QEMU models (SysTick, mtime), calibrates it against a loop of known
# length, and prints SCALAR.instructions=N.
ICOUNT="-icount shift=0,align=off,sleep=off"
# board  target-triple  cargo-profile  packet-width  scalars  qemu command (ELF appended; "-": not run)
#   [cargo selection: package, binary, features; default `-p raypack-BOARD`]
# The ELF is target/TRIPLE/PROFILE/raypack-BOARD (a package's binary of that name).
# Profiles (targets/Cargo.toml): `release` optimizes for speed (the
# Cortex-M4F); the boards with small flash or soft-float use
# `release-small` (opt-level "s"), except the Pico (2 MB of flash; at
# "s" a division in rp2040-hal's clock set-up stays unfolded and the
# panic-never link fails). The scalar-core boards trace one ray at a time:
# in-order scalar cores gain nothing from packets, and each packet width
# multiplies the code (measured on the M4F: 110 KB at width 1, 208 KB at 8);
# the host proves the bytes equal at every width (tests/firmware_checksum.rs).
# The vector boards (Helium, RVV; width column "-") run widths 1, 4 and 8,
# one label per width (docs/firmware.md).
BOARDS=(
  "mps2-an386|thumbv7em-none-eabihf|release|1|f32,fixed32|qemu-system-arm -cpu cortex-m4 -M mps2-an386 -nographic -semihosting-config enable=on,target=native $ICOUNT -kernel"
  # Cortex-M55 with Helium (MVE, 4 f32 lanes per 128-bit register): the same
  # f32 frame at packet widths 1, 4 and 8 (labels SCALAR-wN, each compared
  # with the host's SCALAR line), and fixed32 at width 1.
  "mps3-an547|thumbv8m.main-none-eabihf|release|-|f32-w1,f32-w4,f32-w8,fixed32-w1|qemu-system-arm -M mps3-an547 -nographic -semihosting-config enable=on,target=native $ICOUNT -kernel"
  "microbit|thumbv6m-none-eabi|release-small|1|f32,fixed32|qemu-system-arm -cpu cortex-m0 -M microbit -nographic -semihosting-config enable=on,target=native $ICOUNT -kernel|-p raypack-microbit --bin raypack-microbit"
  # What a user flashes: the same board, fixed32 only, its scene baked into
  # flash on the host (no scene code), the Q8.24 multiply out of line
  # (raypack's `compact-mul`; docs/firmware.md has the sizes).
  "microbit-fixed32|thumbv6m-none-eabi|release-small|1|fixed32|qemu-system-arm -cpu cortex-m0 -M microbit -nographic -semihosting-config enable=on,target=native $ICOUNT -kernel|-p raypack-microbit --bin raypack-microbit-fixed32 --features compact-mul"
  "riscv-virt|riscv32imac-unknown-none-elf|release-small|1|f32,fixed32|qemu-system-riscv32 -M virt -bios none -nographic -semihosting $ICOUNT -kernel"
  # RV32IMAFC with the vector extension (Zve32f, VLEN 128; QEMU 7.2's
  # `rv32,v=true,vlen=128`): f32 at widths 1/4/8, as on the Helium board.
  "riscv-virt-v|riscv32imafc-unknown-none-elf|release|-|f32-w1,f32-w4,f32-w8|qemu-system-riscv32 -M virt -cpu rv32,v=true,vlen=128,vext_spec=v1.0 -bios none -nographic -semihosting $ICOUNT -kernel"
  # The Pico's image layout under QEMU: Armv6-M code at opt-level 3 (the
  # Pico's profile) on the Cortex-M3 of mps2-an385, the renderer's code and
  # constants copied from flash to RAM by `main` and run there (common's
  # `ram_code.x`), the frame timed as the Pico's two cores split it.
  "mps2-an385|thumbv6m-none-eabi|release|1|fixed32|qemu-system-arm -M mps2-an385 -nographic -semihosting-config enable=on,target=native $ICOUNT -kernel"
  # Raspberry Pi Pico + Pimoroni Pico Display Pack: no QEMU machine models the
  # RP2040, so it is built, sized and proved panic-free only. Its frame is the
  # code the QEMU boards run, split between its two cores (common's dual),
  # host-tested down to the SPI bytes; its instruction counts are
  # mps2-an385's fixed32 shares (the same renderer, profile and layout).
  "rp2040-pico-display|thumbv6m-none-eabi|release|1|fixed32|-"
)
QEMU_TIMEOUT=${RAYPACK_QEMU_TIMEOUT:-300}

# ---------------------------------------------------------------- tools
say "rustup targets and llvm-tools"
rustup target add thumbv7em-none-eabihf thumbv8m.main-none-eabihf thumbv6m-none-eabi riscv32imac-unknown-none-elf riscv32imafc-unknown-none-elf >/dev/null
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
say "firmware support crate: host unit tests (render loop, checksum and panel streams, clock)"
cargo test -q -p raypack-firmware-common --lib --features panel
say "firmware support crate: its documentation builds without warnings (host)"
RUSTDOCFLAGS="-D warnings" cargo doc -q --no-deps -p raypack-firmware-common --features panel

# ---------------------------------------------------------------- downstream
# A downstream crate depending on raypack (path, embedded-graphics adapter),
# the newest mipidsi and embedded-graphics 0.8. Resolved afresh every time:
# `cargo generate-lockfile` ignores any lock and picks what a new application
# would get today, so a raypack requirement that rules out what the display
# crates need (as the former fixed 1.31 dependency's az ^1.3 against
# embedded-graphics-core 0.4.1's az ~1.2 did) fails here. (The targets workspace's committed
# Cargo.lock would hide it: it keeps whatever once resolved.)
say "downstream crate: fresh resolve beside mipidsi, build for thumbv6m-none-eabi"
(cd downstream-display && cargo generate-lockfile -q) \
  || die "downstream-display: raypack no longer resolves beside mipidsi and embedded-graphics (see the resolver's message above)"
awk '/^name = /{n=$3} /^version = /{v=$3; if (n ~ /^"(az|fixed|mipidsi|embedded-graphics|embedded-graphics-core|raypack)"$/) printf "%s %s  ", n, v} END{print ""}' \
  downstream-display/Cargo.lock | tr -d '"' | sed 's/^/resolved: /'
cargo build -q --manifest-path downstream-display/Cargo.toml --target thumbv6m-none-eabi \
  || die "downstream-display: does not build for thumbv6m-none-eabi"

# ---------------------------------------------------------------- boards
SUMMARY=()
SHARES=()
LLVM_NM="$(dirname "$LLVM_SIZE")/llvm-nm"
LLVM_OBJDUMP="$(dirname "$LLVM_SIZE")/llvm-objdump"
# One QEMU run: output to $2, wall time in ms to $2.ms, exit status to $2.rc.
run_qemu() { # $1: ELF, $2: output file
  local start rc
  start=$(date +%s%N)
  set +e
  timeout -k 10 "$QEMU_TIMEOUT" "${qcmd[@]}" "$1" >"$2" 2>&1 </dev/null
  rc=$?
  set -e
  echo $rc >"$2.rc"
  echo $(( ($(date +%s%N) - start) / 1000000 )) >"$2.ms"
}
RUNS=$(mktemp -d)
trap 'rm -rf "$RUNS"' EXIT
for entry in "${BOARDS[@]}"; do
  IFS='|' read -r board triple profile width scalars qemu select <<<"$entry"
  elf="target/$triple/$profile/raypack-$board"
  read -r -a sel <<<"${select:--p raypack-$board}"

  say "$board: build ($profile, LTO)"
  cargo build -q --profile "$profile" "${sel[@]}" --target "$triple" || die "$board: build failed"

  say "$board: sizes"
  "$LLVM_SIZE" -A "$elf" | grep -E '^(section|\.vector_table|\.boot2|\.text|\.rodata|\.data|\.bss|\.uninit|\.init|\.ram_code)' || true
  sec() { "$LLVM_SIZE" -A "$elf" | awk -v s="$1" '$1 == s { print $2; f = 1 } END { if (!f) print 0 }'; }
  # `.ram_code` (the Pico: the renderer's code, stored in flash and run
  # from SRAM) counts in both: flash and RAM.
  text=$(( $(sec .text) + $(sec .init) + $(sec .vector_table) + $(sec .boot2) + $(sec .ram_code) ))
  rodata=$(sec .rodata)
  dataplusbss=$(( $(sec .data) + $(sec .bss) + $(sec .uninit) + $(sec .ram_code) ))
  echo "biggest code and read-only symbols ($(basename "$LLVM_NM") --size-sort -S --demangle, top 10):"
  "$LLVM_NM" --size-sort -S --demangle "$elf" | awk '$3 ~ /^[tTrR]$/' | tail -n 10 | tac \
    | while read -r _addr size _type name; do printf '  %8d  %s\n' "$((16#$size))" "${name:0:110}"; done \
    | sed -e 's/::h[0-9a-f]\{16\}$//' -e 's/_\$LT\$/</g' -e 's/\$LT\$/</g' -e 's/\$GT\$/>/g' -e 's/\$C\$/, /g' -e 's/\$u20\$/ /g' -e 's/\.\./::/g'

  # Hardware-float images: no fused multiply-add anywhere (a fused
  # vfma/fmadd.s/vfmacc would round once where the host rounds twice: other
  # bits). On the vector boards, also count the vector instructions (MVE:
  # operands in q registers; RVV: `v` instructions): the packet lanes must
  # have become vector code.
  fused=; mattr=()
  case $triple in
    thumb*eabihf) fused='^vfn?m[as]' ;;
    riscv32imafc*) fused='^v?fn?m(add|sub|acc|sac)'; mattr=(--mattr=+m,+a,+f,+c,+zve32f) ;;
  esac
  if [ -n "$fused" ]; then
    asm=$("$LLVM_OBJDUMP" -d --no-show-raw-insn "${mattr[@]}" "$elf")
    fma=$(awk -v re="$fused" '$2 ~ re' <<<"$asm" | wc -l)
    echo "fused multiply-add instructions: $fma"
    [ "$fma" -eq 0 ] || die "$board: fused multiply-add in the image (results would differ from the host's)"
    # Arm: no fixed-point `vcvt` (an int/float conversion with a fraction-bit
    # count). LLVM 22 folds `sitofp(x) · 2⁻ⁿ` into one, and at times emits
    # its count as a register, which encodes as another count: the M55
    # rendered fixed32 with ellipsoid bounds 2¹⁴ times too large. The core
    # converts without that product (`Fixed32::to_f32`); a new one fails here.
    if [[ $triple == thumb* ]]; then
      fixcvt=$(awk '$2 ~ /^vcvt/ && $NF ~ /^#/' <<<"$asm")
      echo "fixed-point vcvt instructions: $(grep -c . <<<"$fixcvt" || true)"
      [ -z "$fixcvt" ] || { head -5 <<<"$fixcvt" >&2; die "$board: fixed-point vcvt in the image (LLVM may encode its fraction bits wrongly)"; }
    fi
    case $board in
      mps3-an547) vec=$(grep -cE '[[:space:],{]q[0-7]([],}]|$)' <<<"$asm" || true); kind="MVE (q-register operands)" ;;
      riscv-virt-v) vec=$(awk '$2 ~ /^v/' <<<"$asm" | wc -l); kind="RVV" ;;
      *) vec= ;;
    esac
    if [ -n "$vec" ]; then
      echo "$kind instructions: $vec of $(grep -cE '^ *[0-9a-f]+:' <<<"$asm") in the image"
      [ "$vec" -gt 1000 ] || die "$board: the packet code did not become vector code"
    fi
  fi

  # The renderer run from RAM (common's `ram_code.x`, copied by `main`;
  # docs/firmware.md, "XIP cache misses on the RP2040"): on the Pico, and on
  # mps2-an385, which runs the same layout under QEMU. The section's
  # segment loads from flash and runs in RAM, and every function of raypack
  # and of the common crate is in it.
  case $board in
    rp2040-pico-display) ram_flash="0x10000100 0x10200000"; own=_ZN27raypack_rp2040_pico_display ;;
    mps2-an385) ram_flash="0x0 0x400000"; own=_ZN18raypack_mps2_an385 ;;
    *) ram_flash= ;;
  esac
  if [ -n "$ram_flash" ]; then
    say "$board: the renderer's code is linked to run from RAM"
    read -r flash_lo flash_hi <<<"$ram_flash"
    sect=$("$LLVM_OBJDUMP" -h "$elf" | awk '$2 == ".ram_code" { print $3, $4, $5 }')
    echo ".ram_code (size, run at, stored at): ${sect:-none}"
    read -r size vma lma <<<"$sect"
    [ -n "${lma:-}" ] && (( 16#$vma == 0x20000000 && 16#$lma >= flash_lo && 16#$lma + 16#$size <= flash_hi )) \
      || die "$board: no .ram_code run at 0x20000000 and stored in flash"
    # (Any function named after raypack but the board crate's own, such as
    # `main`, which runs the copy, and the linker's thunks to RAM.)
    stray=$("$LLVM_NM" "$elf" | awk -v own="^($own|__Thumbv6M)" '$2 ~ /^[tT]$/ && $3 ~ /raypack/ && $3 !~ own && $1 !~ /^200/' | head -n 3)
    [ -z "$stray" ] || die "$board: functions of the renderer outside RAM: $stray"
    echo "every function of raypack and raypack_firmware_common (their impls and generics too) at 0x2000_0000 and up"
  fi

  if [ "$qemu" = "-" ]; then
    say "$board: not run (no QEMU machine for it)"
    out=""; wall=-; match="not run"
  else
    # Determinism: every board runs twice, the two runs side by side (QEMU
    # under -icount runs the guest on one host thread, so on the 2-core CI
    # machine the second run costs little wall time: measured in
    # docs/firmware.md), and the two outputs must be identical, byte for
    # byte: same checksums, same instruction counts, same stack figures.
    say "$board: run under QEMU twice, side by side ($QEMU_TIMEOUT s limit each)"
    read -r -a qcmd <<<"$qemu"
    qcmd[0]="${QEMU_PREFIX}${qcmd[0]}"
    run_qemu "$elf" "$RUNS/$board.1" &
    run_qemu "$elf" "$RUNS/$board.2" &
    wait
    out=$(cat "$RUNS/$board.1")
    echo "$out"
    for r in 1 2; do
      rc=$(cat "$RUNS/$board.$r.rc")
      [ "$rc" -ne 124 ] || die "$board: QEMU timed out after $QEMU_TIMEOUT s (run $r)"
      [ "$rc" -eq 0 ] || { cat "$RUNS/$board.$r" >&2; die "$board: firmware exited with status $rc (run $r)"; }
    done
    grep -q '^result=ok$' <<<"$out" || die "$board: firmware did not report result=ok"
    if ! cmp -s "$RUNS/$board.1" "$RUNS/$board.2"; then
      diff "$RUNS/$board.1" "$RUNS/$board.2" >&2 || true
      die "$board: two runs of the same image printed different output (instruction counts not deterministic?)"
    fi
    wall=$(cat "$RUNS/$board.1.ms" "$RUNS/$board.2.ms" | sort -n | tail -1)
    echo "determinism: both runs printed the same $(wc -l <"$RUNS/$board.1") lines (wall $(cat "$RUNS/$board.1.ms") ms and $(cat "$RUNS/$board.2.ms") ms, side by side)"

    match=yes
    for scalar in ${scalars//,/ }; do
      while read -r s key value; do
        # A label SCALAR-wN (one packet width of SCALAR) is checked against
        # the host's SCALAR line: the bytes are the same at every width.
        [ "$s" = "${scalar%-w*}" ] || continue
        if ! grep -qE "^${scalar}\.${key}=${value}( |\$)" <<<"$out"; then
          echo "MISMATCH on $board ($scalar): host says '$s $key $value'" >&2
          match=NO
        fi
      done <<<"$HOST"
    done
    [ $match = yes ] || die "$board: checksum differs from the host's"
  fi

  # After the run: the release panic-never build replaces the binary run above.
  say "$board: no reachable panic (panic-never link, $profile + LTO)"
  cargo build -q --profile "$profile" "${sel[@]}" --target "$triple" --features panic-never \
    || die "$board: a panic is reachable (the panic-never build did not link)"
  # Stricter, opt-in: overflow checks on as well (passed for every board
  # before the BVH merge; not yet re-proved with the BVH traversal).
  if [ "${RAYPACK_OVERFLOW_PROOF:-0}" = 1 ]; then
    say "$board: no reachable panic with overflow checks on (profile panic-never)"
    cargo build -q --profile panic-never "${sel[@]}" --target "$triple" --features panic-never \
      || die "$board: a panic (or integer overflow) is reachable with overflow checks on"
  fi

  # Helium: the image of the fastest f32 width alone (the features choose
  # the frames it holds), its code within the 160 KiB goal of issue 23.
  if [ "$board" = mps3-an547 ]; then
    best=$(sed -n 's/^f32-w\([0-9]*\)\.instructions=\([0-9]*\)$/\2 \1/p' <<<"$out" | sort -n | head -1 | cut -d' ' -f2)
    [ -n "$best" ] || die "$board: no f32-wN.instructions line"
    say "$board: image of the fastest width alone (f32, width $best)"
    cargo build -q --profile "$profile" -p "raypack-$board" --target "$triple" --no-default-features --features "f32-w$best" \
      || die "$board: the width-$best image did not build"
    one=$(( $(sec .text) + $(sec .vector_table) ))
    echo "f32-w$best alone: .text $one bytes (goal: at most $((160 * 1024)))"
    [ "$one" -le $((160 * 1024)) ] || die "$board: the width-$best image has $one bytes of .text, over 160 KiB"
  fi

  # What a user flashes: the fixed32-only Cortex-M0 image (its scene baked
  # into flash) within issue 22's 48 KiB, code and read-only data together.
  if [ "$board" = microbit-fixed32 ]; then
    flash=$((text + rodata))
    echo "flash: .text $text + .rodata $rodata = $flash bytes (goal: .text at most $((48 * 1024)))"
    [ "$flash" -le $((48 * 1024)) ] || die "$board: $flash bytes of code and read-only data, over 48 KiB"
  fi

  if [ -n "$out" ]; then
    stack=$(sed -n 's/^stack-high-water=\([0-9]*\).*/\1/p' <<<"$out")
    sram="$(sed -n 's/^static-ram=\([0-9]*\).*/\1/p' <<<"$out")"
    ram="$dataplusbss ($sram)"
  else
    stack="not run"
    ram="$dataplusbss"
  fi
  for scalar in ${scalars//,/ }; do
    if [ -n "$out" ]; then
      instr=$(sed -n "s/^${scalar}\.instructions=\([0-9]*\)\$/\1/p" <<<"$out")
      pixels=$(sed -n "s/^${scalar}\.pixels=\([0-9]*\)\$/\1/p" <<<"$out")
      rays=$(sed -n "s/^${scalar}\.rays=\([0-9]*\).*/\1/p" <<<"$out")
      [ -n "$instr" ] && [ -n "$pixels" ] && [ -n "$rays" ] || die "$board: no $scalar.instructions/pixels/rays line"
      counts=$(awk -v i="$instr" -v p="$pixels" -v r="$rays" 'BEGIN { printf "%.0f | %.0f | %.0f", i, i / p, i / r }')
      wall_s=$(printf '%d.%03d s' $((wall / 1000)) $((wall % 1000)))
    else
      counts="not run | | "
      wall_s="-"
    fi
    w=$width
    [ "$scalar" = "${scalar%-w*}" ] || w=${scalar##*-w}
    SUMMARY+=("| $board | ${scalar%-w*} | $w | $text | $rodata | $ram | $stack | $counts | $match | $wall_s |")
    # Two-core shares (firmware that times its bands as the Pico splits them).
    if [ -n "$out" ] && grep -q "^${scalar}\.per-core\.instructions=" <<<"$out"; then
      share() { sed -n "s/^${scalar}\.$1\.instructions=\([0-9]*\)\$/\1/p" <<<"$out"; }
      SHARES+=("| $board | $scalar | $(share per-core) | $(share core0) | $(share core1) | $(share lockstep) | $instr |")
    fi
  done
done

say "summary (sizes in bytes; static RAM from llvm-size, in parentheses as measured on the chip; instructions: scene build + render + checksum fold of one frame, under -icount shift=0; QEMU wall time: the slower of the two side-by-side runs, for both scalars)"
echo "| board | scalar | width | .text | .rodata | .data+.bss | stack high-water | instructions / frame | / pixel | / ray | checksum = host | QEMU wall time |"
echo "| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |"
printf '%s\n' "${SUMMARY[@]}"
if [ ${#SHARES[@]} -gt 0 ]; then
  say "two cores (the Pico's split: bands of 1 row alternating between the cores; each share includes the scene build; lockstep: the cores go band pair by band pair)"
  echo "| board | scalar | per-core instructions (larger share) | core 0 | core 1 | lockstep | one core |"
  echo "| --- | --- | --- | --- | --- | --- | --- |"
  printf '%s\n' "${SHARES[@]}"
fi
say "firmware: all boards match the host, every run deterministic"
