// The RP2040's XIP cache, simulated on the instruction fetches of a QEMU
// `-d in_asm,exec,nochain` log on stdin (see README.md, "XIP cache misses").
//
// The cache (RP2040 datasheet, 2.6.3.1 "XIP Cache"): 16 KiB, two-way set
// associative, 8-byte lines, so 1024 sets; a hit takes one cycle, a miss a
// QSPI transfer. Replacement is taken to be least recently used (with two
// ways, one bit per set). Every executed block fetches the 8-byte lines its
// bytes span, in address order; repeated fetches of a line inside a block
// are hits and are not counted. Data reads from flash (constant tables)
// are not in the log and not simulated.
//
// Arguments: [LO HI] in hex: count only from the first block executed in
// [LO, HI) on (for example a frame's function), as well as the whole log.
// Prints the blocks executed, the line fetches, and the misses of both.
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <ctype.h>

#define TBS (1 << 22)     // block table: addresses below 4 MiB (microbit flash)
#define MAX_SETS 65536
#define LINE 8

static unsigned sets = 1024;  // XIP_SETS in the environment: other sizes, for comparison
static unsigned tb_end[TBS];  // one past the last byte of the block starting here
static unsigned tag[MAX_SETS][2];
static unsigned char valid[MAX_SETS][2], lru[MAX_SETS];  // lru: the way to replace next
static unsigned char seen[TBS / LINE];  // lines fetched at least once while counting

static int hex4(const char *p) {
  for (int i = 0; i < 4; i++)
    if (!isxdigit((unsigned char)p[i])) return 0;
  return 1;
}

// One line fetch; returns 1 on a miss.
static int fetch(unsigned line) {
  unsigned set = line % sets, t = line / sets;
  for (int w = 0; w < 2; w++)
    if (valid[set][w] && tag[set][w] == t) {
      lru[set] = (unsigned char)(1 - w);
      return 0;
    }
  int w = lru[set];
  tag[set][w] = t;
  valid[set][w] = 1;
  lru[set] = (unsigned char)(1 - w);
  return 1;
}

int main(int argc, char **argv) {
  const char *e = getenv("XIP_SETS");
  if (e) sets = (unsigned)strtoul(e, 0, 10);
  if (sets < 1 || sets > MAX_SETS) sets = 1024;
  unsigned lo = argc > 2 ? strtoul(argv[1], 0, 16) : 1, hi = argc > 2 ? strtoul(argv[2], 0, 16) : 0;
  char line[4096];
  int in = 0;
  unsigned first = 0;
  int have_first = 0;
  unsigned long long blocks[2] = {0, 0}, fetches[2] = {0, 0}, misses[2] = {0, 0}, unknown = 0;
  int counting = argc > 2 ? 0 : 1;
  while (fgets(line, sizeof line, stdin)) {
    if (line[0] == 'T' && !strncmp(line, "Trace", 5)) {
      char *p = strchr(line, '[');
      if (!p) continue;
      p = strchr(p, '/');
      if (!p) continue;
      unsigned pc = strtoul(p + 1, 0, 16);
      if (!counting && pc >= lo && pc < hi) counting = 1;
      if (pc >= TBS || !tb_end[pc]) {
        unknown++;
        continue;
      }
      for (int k = 0; k < 1 + counting; k++) blocks[k]++;
      for (unsigned l = pc / LINE; l <= (tb_end[pc] - 1) / LINE; l++) {
        int m = fetch(l);
        if (counting && l < TBS / LINE) seen[l] = 1;
        for (int k = 0; k < 1 + counting; k++) {
          fetches[k]++;
          misses[k] += (unsigned)m;
        }
      }
      continue;
    }
    if (!strncmp(line, "IN:", 3)) {
      in = 1;
      have_first = 0;
      continue;
    }
    if (in) {
      if (line[0] == '0' && line[1] == 'x') {
        // "0x000000c0:  f023 fb2a  bl ..." (4 bytes) or "0x0002371a:  af00       add ..." (2).
        unsigned pc = strtoul(line, 0, 16);
        char *p = strchr(line, ':');
        if (!p) continue;
        p++;
        while (*p == ' ') p++;
        int size = (hex4(p) && p[4] == ' ' && hex4(p + 5) && p[9] == ' ') ? 4 : 2;
        if (!have_first) {
          first = pc;
          have_first = 1;
        }
        if (first < TBS) tb_end[first] = pc + (unsigned)size;
      } else if (line[0] == '\n') {
        in = 0;
      }
    }
  }
  const char *name[2] = {"whole log", "from the first block in the range"};
  for (int k = 0; k < (argc > 2 ? 2 : 1); k++)
    printf("%s: %llu blocks, %llu line fetches, %llu misses (%.3f %% of fetches)\n", name[k], blocks[k], fetches[k],
           misses[k], fetches[k] ? 100.0 * (double)misses[k] / (double)fetches[k] : 0.0);
  unsigned long long distinct = 0;
  for (unsigned l = 0; l < TBS / LINE; l++) distinct += seen[l];
  printf("cache: %u sets x 2 ways x %d bytes = %u bytes; code lines fetched while counting: %llu (%llu bytes)\n", sets,
         LINE, sets * 2 * LINE, distinct, distinct * LINE);
  if (unknown) printf("(%llu executions of blocks without a translation in the log, not counted)\n", unknown);
  return 0;
}
