#!/usr/bin/env bash
# Checks the machine code of the dispatched render path (x86-64 only):
#  1. no fused multiply-add (vfmadd/vfmsub/vfnmadd/vfnmsub) anywhere in the
#     release binary: FMA would change the bits of the results;
#  2. the AVX2 entry points (the render loop `dispatch::…::run_avx2`, the
#     tracer `…::job_avx2` and the queries `…::closest_hit_avx2`
#     / `transmittance_avx2`) contain packed 256-bit `ymm` arithmetic, and
#     the AVX-512 ones 512-bit `zmm`;
#  3. the dispatched code calls no raypack packet function out of line (an
#     out-of-line callee would be compiled for the baseline only): the only
#     raypack calls allowed are the per-lane patch interpolation (scalar by
#     nature) and the tracer and queries compiled for the same instruction
#     set (which must be called).
# Needs objdump (Debian: binutils). Prints what it found; exits 1 on failure.
set -euo pipefail
cd "$(dirname "$0")/.."

if [ "$(uname -m)" != "x86_64" ]; then
    echo "check-asm: not an x86-64 host; nothing to check"; exit 0
fi
command -v objdump >/dev/null || { echo "check-asm: objdump missing (apt-get install binutils)" >&2; exit 1; }

# The probe calls the same dispatcher entry points as the CLI
# (`dispatch::render_rect` and `Isa::run`) and builds in a fraction of the
# CLI's release build time (no fixed-point or clap/png/rayon code).
cargo build --release --example primary_probe -q
bin=target/release/examples/primary_probe
asm=$(mktemp)
trap 'rm -f "$asm"' EXIT
objdump -d --no-show-raw-insn -C "$bin" >"$asm"

fail=0
fma=$(grep -cE '\svfn?m(add|sub)[0-9a-z]*\s' "$asm" || true)
echo "check-asm: fused multiply-add instructions in the binary: $fma"
[ "$fma" -eq 0 ] || fail=1

# Per entry point: its instruction count and how many use ymm / zmm.
summary=$(awk '
    /^[0-9a-f]+ <.*>:$/ { if (fn != "") print fn, n, y, z; fn = ""; n = y = z = 0 }
    /^[0-9a-f]+ <raypack::host::dispatch::([a-z0-9_]+::)*(run|job|closest_hit|transmittance)_avx(2|512)<.*>:$/ || /^[0-9a-f]+ <raypack::host::dispatch::([a-z0-9_]+::)*(run|job|closest_hit|transmittance)_avx(2|512)>:$/ {
        fn = (($2 ~ /512/) ? "avx512" : "avx2") (($2 ~ /::run_/) ? " render-path" : (($2 ~ /::job_/) ? " tracer" : " queries")); next }
    fn != "" && /\t/ { n++; if (/%ymm/) y++; if (/%zmm/) z++ }
    END { if (fn != "") print fn, n, y, z }' "$asm")
echo "check-asm: dispatched entry points (isa part instructions ymm zmm):"
echo "$summary" | sed 's/^/    /'
for part in render-path tracer queries; do
    ymm=$(echo "$summary" | awk -v p="$part" '$1 == "avx2" && $2 == p { s += $4 } END { print s + 0 }')
    zmm=$(echo "$summary" | awk -v p="$part" '$1 == "avx512" && $2 == p { s += $5 } END { print s + 0 }')
    [ "$ymm" -gt 0 ] || { echo "check-asm: no ymm instructions in the AVX2 $part" >&2; fail=1; }
    [ "$zmm" -gt 0 ] || { echo "check-asm: no zmm instructions in the AVX-512 $part" >&2; fail=1; }
done

calls=$(awk '
    /^[0-9a-f]+ <.*>:$/ { on = ($0 ~ /<raypack::host::dispatch::([a-z0-9_]+::)*(run|job|closest_hit|transmittance)_avx(2|512)(<.*>)?>:$/); next }
    on && /call/ && /<raypack::/ { sub(/^.*call +[0-9a-f]+ /, ""); print }' "$asm" | sort | uniq -c)
echo "check-asm: raypack functions called from dispatched code:"
echo "${calls:-    (none)}" | sed 's/^/    /'
bad=$(echo "$calls" | grep '<raypack::' | grep -vE 'Polygon<S>::shading_normal>|Tracer<S,A,_>::patch_normals>|<raypack::host::dispatch::([a-z0-9_]+::)*(job|closest_hit|transmittance)_avx(2|512)' || true)
if [ -n "$bad" ]; then
    echo "check-asm: packet code called out of line (compiled for the baseline only):" >&2
    echo "$bad" >&2
    fail=1
fi
querycalls=$(echo "$calls" | grep -cE '<raypack::host::dispatch::([a-z0-9_]+::)*(job|closest_hit|transmittance)_avx(2|512)' || true)
[ "$querycalls" -gt 0 ] || { echo "check-asm: the dispatched code never calls the per-ISA tracer and queries" >&2; fail=1; }
[ "$fail" -eq 0 ] && echo "check-asm: ok"
exit "$fail"
