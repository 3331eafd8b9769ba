"""Cycles of an Armv6-M run from its executed instructions (see README.md).

    python3 cycles.py ELF [EXCLUDE_REGEX [INCLUDE_REGEX]]

Reads `prof.txt` (tb_count's six columns) in the current directory and
applies the instruction timings of the Cortex-M0 and Cortex-M0+ technical
reference manuals (ARM DDI 0432C and DDI 0484C, "Instruction set summary";
single-cycle multiplier, as on the nRF51 and RP2040) to every executed
instruction, with the taken and not-taken counts of each conditional
branch from the block that ran next. Memory is taken to answer without
wait states (the nRF51's flash at 16 MHz, the RP2040's SRAM or a hit in its
XIP cache): what a miss costs is not in the figure.

Blocks of functions whose name matches EXCLUDE_REGEX (default: the timer
calibration's busy loop, by name or as `??`: where it is inlined its
`asm!` block has no line table, so the symboliser cannot name it) are
left out, so that the figure is the frame's;
with INCLUDE_REGEX, only blocks with a function (inlined ones included)
whose name matches it are counted (for example `Fixed32` for a two-scalar
image's fixed-point code).
Prints instructions, cycles and cycles per instruction for both cores, and
the cycles by kind of instruction.
"""
import bisect
import re
import subprocess
import sys
from collections import Counter

T = '/root/.rustup/toolchains/stable-x86_64-unknown-linux-gnu/lib/rustlib/x86_64-unknown-linux-gnu/bin/'
elf = sys.argv[1]
exclude = re.compile(sys.argv[2] if len(sys.argv) > 2 else r'busy_loop|^\?\?$')
include = re.compile(sys.argv[3]) if len(sys.argv) > 3 else None

# Disassembly: address -> (mnemonic, operands), sizes from the next address.
dis = subprocess.run([T + 'llvm-objdump', '-d', '--no-show-raw-insn', elf], capture_output=True, text=True).stdout
insn = {}
for line in dis.split('\n'):
    m = re.match(r'\s*([0-9a-f]+):\s+(\S+)\s*(.*)', line)
    if m:
        insn[int(m.group(1), 16)] = (m.group(2), m.group(3).split('@')[0].strip())
addrs = sorted(insn)
size = {a: (b - a) for a, b in zip(addrs, addrs[1:])}

# Blocks to leave out: those whose first instruction belongs to a function
# (the innermost, inlined ones included) matching `exclude`.
prof = [line.split() for line in open('prof.txt')]
sym = subprocess.run(['/usr/lib/llvm-14/bin/llvm-symbolizer', '--obj=' + elf, '--functions=short', '--demangle', '--inlining'],
                     input='\n'.join('0x' + f[0] for f in prof), capture_output=True, text=True).stdout
skip = set()
for f, frames in zip(prof, sym.strip('\n').split('\n\n')):
    names = frames.strip().split('\n')[0::2]
    if names and exclude.search(names[0]) or include and not any(include.search(n) for n in names):
        skip.add(int(f[0], 16))


def regs(ops):
    """Registers in a register list `{r4, r5, lr}`."""
    m = re.search(r'\{([^}]*)\}', ops)
    return [r.strip() for r in m.group(1).split(',')] if m else []


BRANCH = re.compile(r'b(eq|ne|cs|hs|cc|lo|mi|pl|vs|vc|hi|ls|ge|lt|gt|le)')


def classify(mn, ops, taken):
    """(kind, Cortex-M0 cycles, Cortex-M0+ cycles) of one execution;
    `taken` for a conditional branch."""
    base = mn.split('.')[0]
    if base in ('push', 'pop', 'stm', 'stmia', 'ldm', 'ldmia'):
        n = len(regs(ops))
        if base == 'pop' and 'pc' in regs(ops):
            return 'push/pop/ldm/stm', 4 + n, 3 + n
        return 'push/pop/ldm/stm', 1 + n, 1 + n
    if base.startswith('ldr') or base.startswith('str'):
        return 'load/store', 2, 2
    if base == 'bl':
        return 'branch/call', 4, 3
    if base in ('bx', 'blx', 'b'):
        return 'branch/call', 3, 2
    if BRANCH.fullmatch(base):
        return ('branch/call', 3, 2) if taken else ('branch/call', 1, 1)
    if base in ('mov', 'add') and ops.startswith('pc'):
        return 'other', 3, 2
    if base in ('mrs', 'msr', 'dmb', 'dsb', 'isb'):
        return 'other', 4, 3
    return ('muls' if base == 'muls' else 'other'), 1, 1


n_insn = 0
cyc = [0, 0]
by_kind = Counter()
by_kind_n = Counter()
for f in prof:
    start, execs, last = int(f[0], 16), int(f[1]), int(f[3], 16)
    fall = {2: int(f[4]), 4: int(f[5])} if len(f) >= 6 else {2: 0, 4: 0}
    if start in skip:
        continue
    i = bisect.bisect_left(addrs, start)
    while i < len(addrs) and addrs[i] <= last:
        a = addrs[i]
        mn, ops = insn[a]
        if a == last:
            # The block's last instruction: a branch is taken in every
            # execution after which the next block did not start right
            # after it.
            not_taken = fall.get(size.get(a, 2), 0)
            parts = [(execs - not_taken, True), (not_taken, False)]
        else:
            parts = [(execs, False)]
        for n, taken in parts:
            k, c0, c1 = classify(mn, ops, taken)
            cyc[0] += n * c0
            cyc[1] += n * c1
            by_kind[k] += n * c1
            by_kind_n[k] += n
        n_insn += execs
        i += 1

print(f'instructions {n_insn}')
print(f'cycles Cortex-M0  {cyc[0]}  per instruction {cyc[0] / n_insn:.3f}')
print(f'cycles Cortex-M0+ {cyc[1]}  per instruction {cyc[1] / n_insn:.3f}')
print('Cortex-M0+ cycles by kind (instructions, cycles, share of cycles):')
for k, v in by_kind.most_common():
    print(f'  {k:18s} {by_kind_n[k]:12d} {v:12d} {100 * v / cyc[1]:5.1f} %')
