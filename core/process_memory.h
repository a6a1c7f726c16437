// lockstep core: how the process's heap treats freed memory (glibc malloc).
//
// By default glibc gives freed memory back to the kernel eagerly: blocks of
// 128 KiB and more (more, as the threshold adapts) are mmapped and unmapped
// one by one, and the top of the heap is trimmed whenever 128 KiB are free.
// A program that allocates, frees and allocates again the same sizes (a frame,
// a scanline's compression buffer in OpenEXR's writer, a marching-cubes slab)
// then touches fresh pages every time: a first touch of a 4 KiB page costs a
// minor fault, about 2 us on the 2-core VM lockstep is measured on.
//
// Measured (a one-shot `lockstep render balls-1.nff --algo ray_trace --size
// 256x256 --threads 1 -o x.exr`, machine loaded): 8,800 minor faults, 772
// madvise and 760 brk calls, 0.19-0.21 s of system time with the defaults;
// 980 faults and 0.01-0.03 s with trimming off. The PNG writer, which frees
// little, went from 3,500 faults to about 1,000.
//
// keep_freed_memory(): nothing freed goes back to the kernel before the
// process ends, and no block is mmapped on its own (every block comes from
// the heap, so a freed frame is the next frame's memory: warm, no faults).
// The CLI and the benchmarks call it first thing; a process lives for one
// command, so what it frees it reuses or ends with. Large buffers then sit
// one after another in the heap: Image's allocator (core/image.h) keeps them
// a page apart, which the compositor's speed depends on.
#pragma once

namespace lockstep {

void keep_freed_memory();

}  // namespace lockstep

namespace lockstep {

// What the process has used so far (getrusage, every thread): page faults
// (minor: a page mapped without reading a file; major: read from a file) and
// CPU time in the kernel and in user code. The CLI's stats line gives the
// frame's share and the call's (issue #35).
struct ResourceUse {
  long minor_faults = 0, major_faults = 0;
  double system_seconds = 0, user_seconds = 0;
};
ResourceUse resource_use();

}  // namespace lockstep
