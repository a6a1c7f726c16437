// lockstep optimized: 2D tiles over a TBB task arena (see tiling.h).
#include "optimized/tiling.h"

#include <tbb/blocked_range2d.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <atomic>
#include <mutex>
#include <system_error>

namespace lockstep::opt {

ThreadPoolStart::ThreadPoolStart() {
  try {
    thread_ = std::thread([] {
      tbb::task_arena arena(std::max(1, tbb::this_task_arena::max_concurrency()));
      arena.execute([] { tbb::parallel_for(0, 2, [](int) {}); });
    });
  } catch (const std::system_error&) {
    // No thread to spare: TBB starts at the first frame, as before.
  }
}

ThreadPoolStart::~ThreadPoolStart() {
  if (thread_.joinable()) thread_.join();
}

int resolve_threads(int threads) {
  return threads > 0 ? threads : tbb::this_task_arena::max_concurrency();
}

void parallel_tiles(int width, int height, int tile_w, int tile_h, int threads,
                    const std::function<void(double)>& progress, const TileBody& body) {
  if (width <= 0 || height <= 0) {
    if (progress) progress(1.0);
    return;
  }
  tile_w = std::clamp(tile_w, 1, width);
  tile_h = std::clamp(tile_h, 1, height);
  const int tiles_x = (width + tile_w - 1) / tile_w;
  const int tiles_y = (height + tile_h - 1) / tile_h;
  const long total = long(tiles_x) * long(tiles_y);
  // Report about every 1% of the tiles (and the last one).
  const long every = std::max(1L, total / 100);
  std::atomic<long> done{0};
  std::mutex progress_mutex;
  long reported = 0;  // guarded by progress_mutex

  auto run_tile = [&](int tx, int ty) {
    const int x0 = tx * tile_w, y0 = ty * tile_h;
    body(x0, y0, std::min(width, x0 + tile_w), std::min(height, y0 + tile_h));
    const long n = ++done;
    if (progress && n % every == 0 && n < total) {
      std::lock_guard<std::mutex> lock(progress_mutex);
      if (n > reported) {  // never report going backwards
        reported = n;
        progress(double(n) / double(total));
      }
    }
  };

  tbb::task_arena arena(resolve_threads(threads));
  arena.execute([&] {
    tbb::parallel_for(tbb::blocked_range2d<int>(0, tiles_y, 1, 0, tiles_x, 1),
                      [&](const tbb::blocked_range2d<int>& r) {
                        for (int ty = r.rows().begin(); ty < r.rows().end(); ++ty)
                          for (int tx = r.cols().begin(); tx < r.cols().end(); ++tx)
                            run_tile(tx, ty);
                      });
  });
  if (progress) {
    std::lock_guard<std::mutex> lock(progress_mutex);
    progress(1.0);
  }
}

}  // namespace lockstep::opt
