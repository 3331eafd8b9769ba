#!/usr/bin/env python3
"""Checks the preview's WebAssembly module: it imports nothing, it exports
the calls web/worker.js uses, it uses SIMD (simd128), and, without its
custom sections (names, producers: what --strip-to writes and the page
loads), it is at most --max-kb kilobytes (1 KB = 1000 bytes).

With --panic-paths (needs wabt's wasm-objdump and a module with its name
section: the module as rustc links it, or the one given with --panic-from):
no path of direct or indirect calls leads from any export but rp_load to
the panic handler, and from rp_load only through core's float parser
(core::num::dec2flt, whose bounds checks the optimizer keeps): every
function that calls one of core's panic functions is listed, and any
outside dec2flt fails the check.

    python3 web/test/check_module.py MODULE.wasm --strip-to web/dist/raypack_web.wasm --max-kb 200 \
        [--panic-paths [--panic-from LINKED.wasm]]
"""
import argparse
import re
import subprocess
import sys

EXPORTS = {
    "memory", "rp_text_buffer", "rp_load", "rp_load_demo", "rp_setup", "rp_render_band", "rp_band_y",
    "rp_rgba", "rp_stream", "rp_stream_len", "rp_info", "rp_rays", "rp_checksum", "rp_message",
    "rp_message_len",
}


def leb(d, i):
    r = s = 0
    while True:
        b = d[i]
        i += 1
        r |= (b & 0x7F) << s
        s += 7
        if b < 0x80:
            return r, i


def name(d, i):
    n, i = leb(d, i)
    return d[i:i + n].decode(), i + n


def sections(data):
    if data[:4] != b"\0asm":
        raise ValueError("not a WebAssembly module")
    i = 8
    while i < len(data):
        sid = data[i]
        size, i = leb(data, i + 1)
        yield sid, data[i:i + size]
        i += size


# Exports that must have no path to a panic: all but the one that reads NFF
# text (core's float parser keeps bounds checks, see docs/web.md).
PANIC_FREE = EXPORTS - {"memory", "rp_load"}
# Where the panic calls left may be: core's float parser (`str::parse::<f32>`).
ALLOWED_SITES = "core::num::dec2flt::"


def strip(data):
    """The module without its custom sections."""
    out = bytearray(data[:8])
    i = 8
    while i < len(data):
        start = i
        sid = data[i]
        size, j = leb(data, i + 1)
        i = j + size
        if sid != 0:
            out += data[start:i]
    return bytes(out)


def short(name):
    """A readable path from a mangled Rust name (legacy `_ZN` or v0 `_R`)."""
    body = re.sub(r"Cs[0-9A-Za-z]*_", "", re.sub(r"17h[0-9a-f]{16}E$", "", name))  # hash, v0 crate ids
    segs, i = [], 0
    while i < len(body):
        m = re.match(r"(\d+)", body[i:])
        if not m:
            i += 1
            continue
        n, i = int(m.group(1)), i + len(m.group(1))
        seg = body[i:i + n]
        if n and re.fullmatch(r"[A-Za-z_$.][\w$.]*", seg) and not re.fullmatch(r"h[0-9a-f]{16}", seg):
            segs.append(seg)
            i += n
    text = "::".join(segs) or name
    for a, b in (("$LT$", "<"), ("$GT$", ">"), ("$C$", ","), ("$u20$", " "), ("$RF$", "&"), ("..", "::")):
        text = text.replace(a, b)
    return text


def panic_paths(path):
    """Exports that can reach the panic handler, and the panic call sites."""
    dis = subprocess.run(["wasm-objdump", "-d", path], capture_output=True, text=True, check=True).stdout
    hdr = subprocess.run(["wasm-objdump", "-x", path], capture_output=True, text=True, check=True).stdout
    calls, names, indirect, func = {}, {}, set(), None
    for line in dis.splitlines():
        m = re.match(r"^[0-9a-f]+ func\[(\d+)\] <(.*)>:$", line)
        if m:
            func = int(m.group(1))
            names[func] = m.group(2)
            calls[func] = set()
            continue
        m = re.search(r"\| +call (\d+) <", line)
        if m and func is not None:
            calls[func].add(int(m.group(1)))
        elif "call_indirect" in line and func is not None:
            indirect.add(func)
    table = {int(m.group(1)) for m in re.finditer(r"elem\[\d+\] = func\[(\d+)\]", hdr)}
    exports = {m.group(2): int(m.group(1)) for m in re.finditer(r"- func\[(\d+)\] <[^>]*> -> \"(\w+)\"", hdr)}
    handler = [f for f, n in names.items() if "rust_begin_unwind" in n]
    if not names or not handler:
        raise SystemExit("check_module: no name section or no panic handler found (build with names)")
    for f in indirect:  # an indirect call may reach any function of the table
        calls[f] |= table
    # Functions that reach the handler: fixed point over the call graph.
    reach = set(handler)
    changed = True
    while changed:
        changed = False
        for f, cs in calls.items():
            if f not in reach and cs & reach:
                reach.add(f)
                changed = True
    core_panics = {f for f, n in names.items() if "panicking" in n or "slice_index_fail" in n
                   or "unwrap_failed" in n or "slice_error_fail" in n or "expect_failed" in n}
    sites = sorted({short(names[f]) for f, cs in calls.items()
                    if cs & core_panics and f not in core_panics and f not in handler})
    return {e: f in reach for e, f in exports.items()}, sites


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("wasm")
    ap.add_argument("--max-kb", type=float, default=200)
    ap.add_argument("--strip-to", help="write the module without custom sections here (size checked on it)")
    ap.add_argument("--panic-paths", action="store_true")
    ap.add_argument("--panic-from", help="the module (with names) whose call graph --panic-paths walks")
    a = ap.parse_args()
    data = open(a.wasm, "rb").read()
    fail = []
    if a.panic_paths:
        exports, sites = panic_paths(a.panic_from or a.wasm)
        bad = sorted(e for e in PANIC_FREE if exports.get(e, True))
        load = sorted(e for e, r in exports.items() if r and e not in PANIC_FREE)
        print(f"panic paths: none from {', '.join(sorted(PANIC_FREE - set(bad)))}")
        print(f"panic paths: reachable from {', '.join(load) or 'nothing else'}; bounds checks kept in: "
              + ("; ".join(sites) or "none"))
        if bad:
            fail.append(f"a panic is reachable from {', '.join(bad)} (only rp_load may reach one)")
        others = [s for s in sites if not s.startswith(ALLOWED_SITES)]
        if others:
            fail.append(f"panic calls outside {ALLOWED_SITES}: {'; '.join(others)}")
    imports, exports, data_bytes, pages, simd = [], set(), 0, 0, False
    for sid, body in sections(data):
        if sid == 2:  # imports
            n, j = leb(body, 0)
            for _ in range(n):
                mod, j = name(body, j)
                fld, j = name(body, j)
                imports.append(f"{mod}.{fld}")
                kind = body[j]
                j += 1
                if kind != 0:  # only functions are expected; stop parsing the rest
                    break
                _, j = leb(body, j)
        elif sid == 7:  # exports
            n, j = leb(body, 0)
            for _ in range(n):
                fld, j = name(body, j)
                j += 1
                _, j = leb(body, j)
                exports.add(fld)
        elif sid == 5:  # memory
            _, j = leb(body, 0)
            pages, _ = leb(body, j + 1)
        elif sid == 11:
            data_bytes = len(body)
        elif sid == 0:
            cname, j = name(body, 0)
            if cname == "target_features" and b"simd128" in body[j:]:
                simd = True
    if a.strip_to:
        data = strip(data)
        open(a.strip_to, "wb").write(data)
    size = len(data)
    print(f"module: {size} bytes ({size / 1000:.1f} KB), data {data_bytes} bytes, "
          f"linear memory {pages * 64 // 1024} MiB at start, imports {len(imports)}, simd128 {'yes' if simd else 'no'}", flush=True)
    if imports:
        fail.append(f"the module imports {', '.join(imports)} (worker.js instantiates it with no imports)")
    missing = EXPORTS - exports
    if missing:
        fail.append(f"exports missing: {', '.join(sorted(missing))}")
    if not simd:
        fail.append("not built with simd128 (web/.cargo/config.toml)")
    if size > a.max_kb * 1000:
        fail.append(f"{size} bytes is over the {a.max_kb:g} KB budget")
    for f in fail:
        print(f"check_module: FAIL: {f}", file=sys.stderr)
    return 1 if fail else 0


if __name__ == "__main__":
    sys.exit(main())
