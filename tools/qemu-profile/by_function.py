import sys,subprocess
# Instructions per function from prof.txt (see README.md): by_function.py ELF
from collections import Counter
elf=sys.argv[1]; inl=len(sys.argv)>2
prof=[l.split() for l in open('prof.txt')]
args=['/usr/lib/llvm-14/bin/llvm-symbolizer','--obj='+elf,'--functions=linkage','--demangle']
if not inl: args.append('--no-inlines')
out=subprocess.run(args,input='\n'.join('0x'+p[0] for p in prof),capture_output=True,text=True).stdout
blocks=out.strip('\n').split('\n\n')
c=Counter(); cl=Counter()
for p,blk in zip(prof,blocks):
    ls=blk.strip().split('\n')
    fn=ls[0]; w=int(p[1])*int(p[2])
    c[fn]+=w
    if inl: cl[ls[0]+' @ '+ls[1].split('/')[-1]]+=w
tot=sum(c.values())
for f,v in c.most_common(40): print(f"{v/1e6:8.1f}M {100*v/tot:5.1f}% {f[:140]}")
