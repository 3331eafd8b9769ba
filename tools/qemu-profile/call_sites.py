import sys,subprocess,re
# Calls to the functions matching ARGV[2], by the calling source line (see README.md).
from collections import Counter
elf=sys.argv[1]; pat=sys.argv[2]; skip=set(sys.argv[3].split(',')) if len(sys.argv)>3 else {'lanes.rs','fixed32.rs','vec3.rs','arith.rs','scalar.rs'}
T='/root/.rustup/toolchains/stable-x86_64-unknown-linux-gnu/lib/rustlib/x86_64-unknown-linux-gnu/bin/'
dis=subprocess.run([T+'llvm-objdump','-d','--no-show-raw-insn','-C',elf],capture_output=True,text=True).stdout
bl={}
for l in dis.split('\n'):
    m=re.match(r'\s*([0-9a-f]+):\s+bl\s+0x[0-9a-f]+ <(.*)>',l)
    if m: bl[int(m.group(1),16)]=m.group(2)
calls=Counter()
for l in open('prof.txt'):
    s,c,n,last=l.split()[:4]; last=int(last,16)
    if last in bl and re.search(pat,bl[last]): calls[last]+=int(c)
tot=sum(calls.values()); print('calls',tot)
addrs=list(calls)
out=subprocess.run(['/usr/lib/llvm-14/bin/llvm-symbolizer','--obj='+elf,'--functions=short','--demangle'],input='\n'.join(hex(a) for a in addrs),capture_output=True,text=True).stdout.strip('\n').split('\n\n')
byfile=Counter(); byline=Counter()
for a,blk in zip(addrs,out):
    ls=blk.strip().split('\n')
    for i in range(0,len(ls),2):
        loc=ls[i+1].split('/')[-1]; f=loc.split(':')[0]
        if f not in skip:
            byfile[f]+=calls[a]; byline[':'.join(loc.split(':')[:2])]+=calls[a]; break
for k,v in byfile.most_common(25): print(f"{v/1e3:9.1f}k {100*v/tot:5.1f}% {k}")
print('--- lines')
for k,v in byline.most_common(int(sys.argv[4]) if len(sys.argv)>4 else 40): print(f"{v/1e3:9.1f}k {100*v/tot:5.1f}% {k}")
