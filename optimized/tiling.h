// lockstep optimized: 2D tiles over a TBB task arena, with progress.
//
// parallel_tiles() cuts a width x height frame into tiles of tile_w x tile_h
// (the last row and column of tiles may be smaller) and runs body(x0, y0, x1,
// y1) once per tile -- half-open bounds, x1 <= width, y1 <= height -- on
// `threads` threads of their own tbb::task_arena (0: all cores), so a caller's
// thread count is honoured whatever arena it is called from. Tiles are handed
// out by TBB's work stealing; nothing is shared between bodies but what the
// caller shares.
//
// progress, when set, is called with the fraction of tiles done, from one
// thread at a time (under a mutex), never with a smaller fraction than before,
// at most about 100 times, and always once with 1.0 at the end. Exceptions
// thrown by a body propagate to the caller (TBB cancels the remaining tiles).
//
// Full-width tiles (tile_w >= width) are bands of rows: for row-major images
// each band is one contiguous range of pixels (how the compositor streams).
#pragma once

#include <functional>
#include <thread>

namespace lockstep::opt {

using TileBody = std::function<void(int x0, int y0, int x1, int y1)>;

void parallel_tiles(int width, int height, int tile_w, int tile_h, int threads,
                    const std::function<void(double)>& progress, const TileBody& body);

// The number of threads parallel_tiles runs for `threads` (0: all cores).
int resolve_threads(int threads);

// Starts TBB on a thread of its own while the caller does something else
// (loads its input): TBB's first arena costs a few ms once per process (its
// scheduler, worker threads, the topology library it opens), which otherwise
// fell into the first frame (issue #21: zbuffer's cold first frame 13-19 ms
// against 3.5-4.2 warm, one thread; 7-11 ms with TBB started beforehand).
// The destructor waits for it. Only what TBB would do anyway at its first
// frame: nothing is left behind but TBB's own process-wide state.
class ThreadPoolStart {
 public:
  ThreadPoolStart();
  ~ThreadPoolStart();
  ThreadPoolStart(const ThreadPoolStart&) = delete;
  ThreadPoolStart& operator=(const ThreadPoolStart&) = delete;

 private:
  std::thread thread_;
};

}  // namespace lockstep::opt
