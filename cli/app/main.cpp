#include <malloc.h>

#include "cli/commands.h"

int main(int argc, char** argv) {
    // Frames allocate and free buffers of tens of megabytes (readback, light-sample buffers, Embree's
    // scene). glibc serves those from fresh mmap'd pages by default and returns them on free, so every
    // frame page-faults its buffers in again, and its adaptive threshold makes the cost vary from run
    // to run; `stsv bench` timed that variance. Keeping blocks up to 32 MiB in the heap and trimming it
    // only above 1 GiB makes a repeated frame reuse its memory.
    mallopt(M_MMAP_THRESHOLD, 32 << 20);
    mallopt(M_TRIM_THRESHOLD, 1 << 30);
    return stsv::runCli(argc, argv);
}
