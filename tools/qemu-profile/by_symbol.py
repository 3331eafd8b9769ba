import sys,subprocess,bisect,re
# Instructions per function from prof.txt, attributed by the symbol table
# (`llvm-nm -S`: address and size) instead of llvm-symbolizer, which names
# RISC-V blocks after local labels (`.L0`): by_symbol.py ELF [N]
from collections import Counter
elf=sys.argv[1]
sysroot=subprocess.run(['rustc','--print','sysroot'],capture_output=True,text=True).stdout.strip()
host=[l.split()[1] for l in subprocess.run(['rustc','-vV'],capture_output=True,text=True).stdout.split('\n') if l.startswith('host:')][0]
NM=f'{sysroot}/lib/rustlib/{host}/bin/llvm-nm'
syms=[]
for l in subprocess.run([NM,'-S','--demangle',elf],capture_output=True,text=True).stdout.split('\n'):
    p=l.split(None,3)
    if len(p)==4 and p[2] in 'tTwW':
        syms.append((int(p[0],16),int(p[1],16),p[3]))
syms.sort()
starts=[s[0] for s in syms]
c=Counter()
for l in open('prof.txt'):
    a,n,k,last=l.split()[:4]; a=int(a,16); w=int(n)*int(k)
    i=bisect.bisect_right(starts,a)-1
    name='?'
    if i>=0 and a < syms[i][0]+max(syms[i][1],1): name=syms[i][2]
    c[re.sub(r'::h[0-9a-f]{16}$','',name)]+=w
tot=sum(c.values())
for f,v in c.most_common(int(sys.argv[2]) if len(sys.argv)>2 else 30): print(f"{v/1e6:8.1f}M {100*v/tot:5.1f}% {f[:130]}")
