// Per translated block of a QEMU `-d in_asm,exec,nochain` log on stdin: start address,
// executions, instructions, last instruction address, and how often the next block
// executed began 2 and 4 bytes after that last instruction's address (its fall-through
// when it is 2 or 4 bytes long: a branch ending the block not taken; see README.md
// and cycles.py). An optional
// argument is the image's load address in hex (RISC-V `virt`: 80000000): addresses are
// counted relative to it, in a table of 4 M entries, and printed absolute.
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#define N (1<<22)
static unsigned long long cnt[N], next2[N], next4[N]; static int ninsn[N]; static unsigned lastpc[N]; unsigned last=0;
int main(int argc,char**argv){ char line[4096]; int in=0; unsigned tbpc=0; int tmp=0; unsigned prev=N;
 unsigned base=argc>1?strtoul(argv[1],0,16):0;
 while(fgets(line,sizeof line,stdin)){
  if(line[0]=='T' && !strncmp(line,"Trace",5)){ char*p=strchr(line,'['); if(!p)continue; p=strchr(p,'/'); if(!p)continue; unsigned pc=strtoul(p+1,0,16)-base; if(pc<N){ cnt[pc]++;
    if(prev<N){ unsigned d=pc-lastpc[prev]; if(d==2) next2[prev]++; else if(d==4) next4[prev]++; } }
   prev=pc; continue;}
  if(!strncmp(line,"IN:",3)){in=1;tbpc=0;tmp=0;continue;}
  if(in){ if(line[0]=='0'&&line[1]=='x'){unsigned pc=strtoul(line,0,16)-base; if(!tbpc){tbpc=pc;} tmp++; last=pc; } else if(line[0]=='\n'){in=0; if(tbpc<N){ ninsn[tbpc]=tmp; lastpc[tbpc]=last;}} }
 }
 for(unsigned i=0;i<N;i++) if(cnt[i]) printf("%x %llu %d %x %llu %llu\n",i+base,cnt[i],ninsn[i],lastpc[i]+base,next2[i],next4[i]);
}
