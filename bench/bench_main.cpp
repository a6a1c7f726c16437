// lockstep benchmarks (Google Benchmark), registered from the registry
// (pairs/registry.h) and the ray-casting kernel rows (pairs/ray_cast.h).
//
//   kernel/<pair>/<impl>          one primitive against 4096 rays, single thread:
//                                 items/s = ray-primitive tests per second
//   throughput/<prims>/<impl>     trace() of 4096 rays against 256 primitives
//   frame/<family>/<input>/<impl>/threads:N  every image family's bench inputs
//                                 (pairs/<family>.cpp), rendered whole: items/s =
//                                 output pixels (primary rays) per second;
//                                 counters build_ms (Embree BVH) and the input's own
//
// Reproduce the tables in BENCHMARKS.md with scripts/bench.sh. The reference is
// scalar and single-threaded by design, so it only runs with threads:1, and on
// scenes above 5000 primitives at 128x128 instead of 512x512 (rays/s is per ray;
// brute force costs the same for every ray, so the rate carries over).
#include <benchmark/benchmark.h>

#include <malloc.h>

#include <algorithm>
#include <limits>
#include <cmath>
#include <cstring>
#include <cstdlib>
#include <filesystem>
#include <optional>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "core/error.h"
#include "core/image.h"
#include "core/nff.h"
#include "core/timer.h"
#include "pairs/ray_cast.h"
#include "pairs/registry.h"

namespace lockstep {
namespace {

// ---------------------------------------------------------------- kernel inputs
// Deterministic rays from a shell around the origin aimed near a unit-size
// primitive at the origin: about half hit. The same seed for every implementation.
std::vector<Ray> rays_around_origin(size_t n, double spread) {
  std::mt19937_64 rng(12345);
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<Ray> rays(n);
  for (auto& r : rays) {
    Vec3 o;
    do o = {u(rng), u(rng), u(rng)}; while (length(o) > 1 || length(o) < 0.1);
    o = normalize(o) * 10.0;
    const Vec3 target{spread * u(rng), spread * u(rng), spread * u(rng)};
    r = Ray{o, normalize(target - o), 0.0, kInfinity};
  }
  return rays;
}

constexpr size_t kKernelRays = 4096;

// Runs f with TBB limited to one thread (trace() of the optimized
// implementations uses TBB's default arena).
template <class F>
void tbb_single_thread(F&& f) {
  tbb::task_arena arena(1);
  arena.execute(f);
}

template <class Fn, class Call>
void register_kernel(const Pair<Fn>& pair, Call call) {
  for (const auto& impl : pair.impls) {
    const std::string name = "kernel/" + std::string(pair.name) + "/" + std::string(impl.name);
    benchmark::RegisterBenchmark(name.c_str(), [fn = impl.fn, call](benchmark::State& st) {
      const std::vector<Ray> rays = rays_around_origin(kKernelRays, 1.5);
      std::vector<double> t(rays.size());
      for (auto _ : st) {
        call(fn, rays, t);
        benchmark::DoNotOptimize(t.data());
        benchmark::ClobberMemory();
      }
      st.SetItemsProcessed(int64_t(st.iterations()) * int64_t(rays.size()));
      size_t hits = 0;
      for (double x : t) hits += std::isfinite(x);
      st.counters["hit_fraction"] = double(hits) / double(rays.size());
    });
  }
}

void register_kernels(const RayCastRows& table) {
  const Sphere sphere{{0, 0, 0}, 1.0};
  register_kernel(table.ray_sphere, [sphere](RaySphereFn fn, const std::vector<Ray>& r, std::vector<double>& t) {
    fn(r, sphere, t);
  });
  const Plane plane{normalize(Vec3{0.3, 0.4, 1.0}), 0.0};
  register_kernel(table.ray_plane, [plane](RayPlaneFn fn, const std::vector<Ray>& r, std::vector<double>& t) {
    fn(r, plane, t);
  });
  // A single triangle: "ray-triangle tests per second".
  auto tri = std::make_shared<Scene>();
  const Vec3 v[3] = {{-1.5, -1, 0.2}, {1.5, -1, -0.2}, {0, 1.5, 0}};
  add_polygon(*tri, v, {}, add_material(*tri, Material{}));
  register_kernel(table.ray_polygon, [tri](RayPolygonFn fn, const std::vector<Ray>& r, std::vector<double>& t) {
    fn(r, *tri, 0, t);
  });
}

// ---------------------------------------------------------------- throughput
// The single-primitive kernels above mostly measure per-call setup for SIMD
// (8 rays against 1 primitive). Here every ray_cast implementation's trace()
// resolves 4096 rays against 256 primitives (random unit spheres in a box, or a
// 16x8 grid of quads = 256 triangles), single thread via a 1-thread arena:
// items/s = ray-primitive pairs per second (brute force tests them all; Embree
// does not, which is the point of a BVH).
Scene throughput_scene(bool spheres) {
  Scene s;
  const uint32_t m = add_material(s, Material{});
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-4, 4);
  if (spheres) {
    for (int i = 0; i < 256; ++i) add_sphere(s, {u(rng), u(rng), u(rng)}, 0.3, m);
  } else {
    for (int i = 0; i < 16; ++i)
      for (int j = 0; j < 8; ++j) {
        const double x = -4 + i * 0.5, y = -4 + j * 1.0, z = 0.2 * std::sin(i + j);
        const Vec3 q[4] = {{x, y, z}, {x + 0.5, y, z}, {x + 0.5, y + 1.0, z}, {x, y + 1.0, z}};
        add_polygon(s, q, {}, m);
      }
  }
  return s;
}

void register_throughput(const RayCastRows& table) {
  for (bool spheres : {true, false}) {
    auto scene = std::make_shared<Scene>(throughput_scene(spheres));
    const double prims = double(scene->sphere_count() + scene->polygon_count() * (spheres ? 1 : 2));
    for (const auto& impl : table.ray_cast.impls) {
      const std::string name = std::string("throughput/") + (spheres ? "spheres/" : "triangles/") + std::string(impl.name);
      benchmark::RegisterBenchmark(name.c_str(), [scene, prims, fn = impl.fn](benchmark::State& st) {
        // Rays from one eye (as primary rays are), spread over the primitives.
        std::vector<Ray> rays = rays_around_origin(kKernelRays, 4.0);
        for (auto& r : rays) {
          const Vec3 target = r.o + 10.0 * r.d;
          r.o = Vec3{0.3, 0.2, 12.0};
          r.d = normalize(target - r.o);
        }
        std::vector<Hit> hits(rays.size());
        tbb_single_thread([&] {
          for (auto _ : st) {
            fn.trace(*scene, rays, hits, nullptr);
            benchmark::DoNotOptimize(hits.data());
          }
        });
        st.SetItemsProcessed(int64_t(double(st.iterations()) * double(rays.size()) * prims));
      })->Unit(benchmark::kMicrosecond);
    }
  }
}

// ---------------------------------------------------------------- frames (every image family)
// frame/<family>/<input>/<impl>/threads:N: the family's bench inputs
// (ImageFamily::bench) rendered whole; items/s = output pixels per second
// (primary rays for ray_cast). Inputs that say how many bytes a run must move
// get frame/<family>/<input>/memcpy/threads:N beside them (unless the input
// says yardstick = false): memcpy of the same bytes (half read, half written)
// on the same number of threads, the bandwidth yardstick. Its buffers are
// plain vectors touched before the loop (measured 25-40% faster here than the
// same copy between page-aligned buffers, so the yardstick is the harder
// one to beat). glibc's memcpy stores through the cache below
// x86_non_temporal_threshold per call (0xf000000 here), so each destination
// line is also read for ownership: the bytes counted are what memcpy is asked
// to move, not what the memory bus carries.
void register_memcpy(const std::string& base, double bytes, int threads) {
  const std::string bname = base + "/memcpy/threads:" + std::to_string(threads);
  benchmark::RegisterBenchmark(bname.c_str(), [bytes, threads](benchmark::State& st) {
    const size_t n = size_t(bytes / 2);
    std::vector<char> src(n, 1), dst(n, 0);  // touched once here, not in the loop
    tbb::task_arena arena(threads);
    for (auto _ : st) {
      arena.execute([&] {
        const size_t chunk = std::max<size_t>(1 << 20, n / size_t(8 * threads));
        tbb::parallel_for(size_t(0), (n + chunk - 1) / chunk, [&](size_t k) {
          const size_t lo = k * chunk, len = std::min(chunk, n - lo);
          std::memcpy(dst.data() + lo, src.data() + lo, len);
        });
      });
      benchmark::DoNotOptimize(dst.data());
      benchmark::ClobberMemory();
    }
    st.SetBytesProcessed(int64_t(double(st.iterations()) * 2 * double(n)));
  })->Unit(benchmark::kMillisecond)->UseRealTime()->MeasureProcessCPUTime();
}

// A large input (a 32-layer 4096^2 stack is 8 GB) is built on first use and
// dropped when a benchmark of another input starts (benchmarks run in
// registration order), so that one is in memory at a time.
struct Holder;
using Cache = std::pair<const Holder*, std::optional<Input>>;
struct Holder {
  BenchInput meta;
  std::shared_ptr<Cache> cache;
  const Input& get() {
    if (!meta.make) return meta.input;
    if (cache->first != this) {
      cache->second.reset();
      cache->second = meta.make();
      cache->first = this;
    }
    return *cache->second;
  }
};

// Warm and cold. The timed loop is warm: each run's frame is freed into the
// heap and the next run reuses it (main() keeps big blocks out of mmap and
// never trims), as a renderer reuses its frame buffer. first_ms is the cold
// run, once per benchmark before its first timed batch: malloc_trim(0) first
// hands the heap's free pages back to the kernel, so the output is fresh pages
// (first touch) and the run includes the thread arena's start.
void register_frames(const Registry& reg) {
  const int all_threads = int(std::max(1u, std::thread::hardware_concurrency()));
  auto cache = std::make_shared<Cache>(nullptr, std::nullopt);
  for (const ImageFamily& fam : reg.image) {
    if (!fam.bench) continue;
    for (const BenchInput& in : fam.bench()) {
      const std::string base = "frame/" + std::string(fam.name) + "/" + in.name;
      auto input = std::make_shared<Holder>();
      input->meta = in;
      input->cache = cache;
      for (int threads : {1, all_threads}) {
        for (const ImageImpl& impl : fam.impls) {
          if (!impl.threaded && threads != 1) continue;  // the reference is single-threaded by design
          // Brute force costs the same for every pixel: the reference runs heavy
          // inputs at a quarter of the size per side and the rate carries over.
          const int div = !impl.threaded && in.heavy_for_reference ? 4 : 1;
          const std::string bname = base + "/" + std::string(impl.name) + "/threads:" + std::to_string(threads);
          auto cold = std::make_shared<double>(-1);  // seconds of the cold run, once per benchmark
          benchmark::RegisterBenchmark(bname.c_str(), [input, div, threads, cold, sized = fam.sized, fn = impl.render,
                                                       unit = std::string(fam.unit)](benchmark::State& st) {
            const Input& in = input->get();
            FrameOptions opts;
            opts.width = input->meta.width / div;
            opts.height = input->meta.height / div;
            opts.threads = threads;
            opts.params = input->meta.params;
            if (*cold < 0) {
              malloc_trim(0);
              FrameStats stats;
              const Stopwatch once;
              Image img = fn(in, opts, &stats);
              *cold = once.seconds();
              benchmark::DoNotOptimize(img.rgba.data());
            }
            double build = 0, items = 0;
            uint64_t pixels = 0;
            for (auto _ : st) {
              FrameStats stats;
              Image img = fn(in, opts, &stats);
              benchmark::DoNotOptimize(img.rgba.data());
              build += stats.build_seconds;
              items += double(stats.items);
              pixels = uint64_t(img.width) * uint64_t(img.height);
            }
            // What the family counts (rays, pixels, triangles), per second of real time.
            st.counters[unit + "_per_s"] = benchmark::Counter(items, benchmark::Counter::kIsRate);
            st.SetItemsProcessed(int64_t(st.iterations() * pixels));
            if (input->meta.bytes > 0) st.SetBytesProcessed(int64_t(double(st.iterations()) * input->meta.bytes));
            st.counters["build_ms"] = 1e3 * build / double(st.iterations());
            st.counters["size"] = sized ? opts.width : input->meta.width;
            st.counters["first_ms"] = 1e3 * *cold;  // cold: fresh output pages, thread start (see above)
            for (const auto& [k, v] : input->meta.counters) st.counters[k] = v;
          })->Unit(benchmark::kMillisecond)->UseRealTime()->MeasureProcessCPUTime();
        }
        if (in.bytes > 0 && in.yardstick) register_memcpy(base, in.bytes, threads);
      }
    }
  }
}

}  // namespace
}  // namespace lockstep

int main(int argc, char** argv) {
  // Warm figures: freed frames stay in the heap and are reused by the next
  // iteration, as a renderer reuses its frame buffer, instead of each 256 MB
  // frame being fresh pages from the kernel (the one-shot cost of first touch
  // is the first_ms counter, see register_frames). Big blocks then come one
  // after another from the heap: Image's allocator keeps them a page apart
  // (core/image.h), which the compositor's speed depends on.
  mallopt(M_MMAP_MAX, 0);
  mallopt(M_TRIM_THRESHOLD, std::numeric_limits<int>::max());
  try {
    lockstep::register_kernels(lockstep::ray_cast_rows());
    lockstep::register_throughput(lockstep::ray_cast_rows());
    lockstep::register_frames(lockstep::registry());
  } catch (const lockstep::InputError& e) {
    std::fprintf(stderr, "lockstep_bench: %s\n", e.what());
    return 2;
  }
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 2;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
