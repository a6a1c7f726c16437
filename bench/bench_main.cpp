// lockstep benchmarks (Google Benchmark), registered from the registry
// (registry/registry.h) and nothing else: bench/ names no family.
//
//   <stage>/<impl>                every family's stage benchmarks (Family::kernels),
//                                 e.g. ray casting's kernel/ray_sphere/simd (one
//                                 primitive against 4096 rays, single thread: items/s
//                                 = ray-primitive tests per second) and
//                                 throughput/spheres/embree (trace() of 4096 rays
//                                 against 256 primitives): registry/ray_cast_row.cpp
//   frame/<family>/<input>/<impl>/threads:N  every family's bench inputs
//                                 (registry/<family>_row.cpp), run whole: items/s =
//                                 output samples (pixels) per second;
//                                 counters build_ms (Embree BVH) and the input's own
//
// Reproduce the tables in BENCHMARKS.md with bench/run.sh. The reference is
// scalar and single-threaded by design, so it only runs with threads:1, and on
// scenes above 5000 primitives at 128x128 instead of 512x512 (rays/s is per ray;
// brute force costs the same for every ray, so the rate carries over).
#include <benchmark/benchmark.h>

#include <malloc.h>  // malloc_trim: the cold run
#include <sys/resource.h>

#include <algorithm>
#include <cstdio>
#include <limits>
#include <cmath>
#include <cstring>
#include <cstdlib>
#include <filesystem>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "core/error.h"
#include "core/output.h"
#include "core/process_memory.h"
#include "core/timer.h"
#include "optimized/tiling.h"
#include "registry/loaders.h"
#include "registry/registry.h"

namespace lockstep {
namespace {

// Runs f with TBB limited to `threads` threads (the optimized implementations
// use TBB's default arena).
template <class F>
void in_arena(int threads, F&& f) {
  tbb::task_arena arena(threads);
  arena.execute(f);
}

// ---------------------------------------------------------------- stages (every family's kernel rows)
// <name>/<impl>: the family's stage benchmarks (Family::kernels, e.g. ray
// casting's kernel/ray_sphere/simd and throughput/spheres/embree), each built
// by the family and timed here: items/s is what the stage says it processed.
void register_kernels(const Registry& reg) {
  for (const Family& fam : reg.families) {
    if (!fam.kernels) continue;
    for (const KernelBench& k : fam.kernels()) {
      for (const KernelBench::Entry& e : k.impls) {
        const std::string name = k.name + "/" + std::string(e.impl);
        auto* b = benchmark::RegisterBenchmark(name.c_str(), [prepare = e.prepare, threads = k.threads](benchmark::State& st) {
          const KernelBench::Run run = prepare();
          int64_t items = 0;
          in_arena(threads, [&] {
            for (auto _ : st) {
              items += run.once();
              benchmark::ClobberMemory();
            }
          });
          st.SetItemsProcessed(items);
          if (run.counters)
            for (const auto& [c, v] : run.counters()) st.counters[c] = v;
        });
        if (k.microseconds) b->Unit(benchmark::kMicrosecond);
      }
    }
  }
}

// ---------------------------------------------------------------- frames (every family)
// frame/<family>/<input>/<impl>/threads:N: the family's bench inputs
// (Family::bench) run whole; items/s = output samples per second (the
// output kind's count: pixels for images; primary rays for ray_cast). Inputs that say how many bytes a run must move
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
//
// first_faults and first_cpu_ms: the cold run's page faults and CPU time.
//
// Rows with a session (FamilyImpl::session: llvmpipe keeps its GL context and
// compiled shaders, composite's simd row its frame buffer, as an application
// does) run every frame of a benchmark in one session: session_ms is its start
// (composite: the frame buffer allocated and touched once; llvmpipe: nothing
// yet), first_ms the session's first frame (llvmpipe: context creation, shader
// compilation), the timed loop its later frames. One session is alive at a
// time (a benchmark's own, started before its cold run), as one input is.
// Minor page faults and CPU seconds (user + system) of the process so far,
// every thread's: the cold run's first touches of fresh pages and its CPU time
// (which a loaded machine's waiting does not inflate), counted beside its wall
// time (first_faults, first_cpu_ms).
long minor_faults() {
  rusage u;
  getrusage(RUSAGE_SELF, &u);
  return u.ru_minflt;
}
double cpu_seconds() {
  rusage u;
  getrusage(RUSAGE_SELF, &u);
  return double(u.ru_utime.tv_sec + u.ru_stime.tv_sec) +
         1e-6 * double(u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}

using RunFn = std::function<Output(const Input&, const FrameOptions&, FrameStats*)>;
struct SessionCache {
  // The benchmark binary's run (core/run_resources.h): what sessions share
  // across benchmarks and rows, the embree rows' one Embree device per process
  // (made by the first embree frame benchmark that runs, in its first_ms).
  // Declared first: run below goes before it.
  RunResources resources;
  const void* owner = nullptr;  // the benchmark whose session run holds
  RunFn run;
};

void register_frames(const Registry& reg) {
  const int all_threads = int(std::max(1u, std::thread::hardware_concurrency()));
  auto cache = std::make_shared<Cache>(nullptr, std::nullopt);
  auto sessions = std::make_shared<SessionCache>();
  for (const Family& fam : reg.families) {
    if (!fam.bench) continue;
    for (const BenchInput& in : fam.bench()) {
      const std::string base = "frame/" + std::string(fam.name) + "/" + in.name;
      auto input = std::make_shared<Holder>();
      input->meta = in;
      input->cache = cache;
      for (int threads : {1, all_threads}) {
        for (const FamilyImpl& impl : fam.impls) {
          if (!impl.threaded && threads != 1) continue;  // the reference is single-threaded by design
          if (&impl == &fam.reference() && !in.reference) continue;  // the input says it would take minutes
          if (impl.unsupported && !impl.unsupported(in.params).empty()) continue;  // e.g. llvmpipe: no Phong
          // Brute force costs the same for every pixel: the reference runs heavy
          // inputs at a quarter of the size per side and the rate carries over
          // (the reference only: a single-threaded peer such as VolPack runs at size).
          const int div = &impl == &fam.reference() && in.heavy_for_reference ? 4 : 1;
          const std::string bname = base + "/" + std::string(impl.name) + "/threads:" + std::to_string(threads);
          auto cold = std::make_shared<double>(-1);  // seconds of the cold run, once per benchmark
          auto cold_faults = std::make_shared<double>(0);  // its page faults (all threads)
          auto cold_cpu = std::make_shared<double>(0);     // its CPU seconds (all threads)
          auto session_start = std::make_shared<double>(-1);  // seconds of the session's start (rows with one)
          benchmark::RegisterBenchmark(bname.c_str(), [input, div, threads, cold, cold_faults, cold_cpu, session_start,
                                                       sized = fam.sized, run = impl.run, session = impl.session, sessions, kind = fam.kind,
                                                       unit = std::string(fam.unit), bname](benchmark::State& st) {
            const Input& in = input->get();
            FrameOptions opts;
            opts.width = input->meta.width / div;
            opts.height = input->meta.height / div;
            opts.threads = threads;
            opts.params = input->meta.params;
            if (sessions->owner != cold.get()) {
              sessions->run = nullptr;  // the previous benchmark's session (its context, its buffers) goes first
              sessions->owner = cold.get();
              if (session) {
                const Stopwatch start;
                sessions->run = session(in, opts, sessions->resources);
                *session_start = start.seconds();
              }
            }
            const RunFn& fn = session ? sessions->run : run;
            if (*cold < 0) {
              malloc_trim(0);
              FrameStats stats;
              const long faults0 = minor_faults();
              const double cpu0 = cpu_seconds();
              const Stopwatch once;
              Output out = fn(in, opts, &stats);
              *cold = once.seconds();
              *cold_cpu = cpu_seconds() - cpu0;
              *cold_faults = double(minor_faults() - faults0);
              benchmark::DoNotOptimize(kind->data(out));
              // What the run says the user must hear (e.g. llvmpipe: its thread
              // count is fixed per process, so threads:N may not be what ran).
              for (const std::string& note : stats.notes) std::fprintf(stderr, "%s: %s\n", bname.c_str(), note.c_str());
            }
            double build = 0, items = 0;
            uint64_t samples = 0;
            std::vector<std::pair<std::string, double>> kinds;  // FrameStats::counts, summed
            for (auto _ : st) {
              FrameStats stats;
              Output out = fn(in, opts, &stats);
              benchmark::DoNotOptimize(kind->data(out));
              build += stats.build_seconds;
              items += double(stats.items);
              samples = kind->count(out);
              if (kinds.size() != stats.counts.size()) kinds.assign(stats.counts.size(), {});
              for (size_t k = 0; k < stats.counts.size(); ++k) {
                kinds[k].first = stats.counts[k].first;
                kinds[k].second += double(stats.counts[k].second);
              }
            }
            for (const auto& [k, v] : kinds)
              st.counters[k + "_per_s"] = benchmark::Counter(v, benchmark::Counter::kIsRate);
            // What the family counts (rays, pixels, triangles), per second of real time.
            st.counters[unit + "_per_s"] = benchmark::Counter(items, benchmark::Counter::kIsRate);
            st.SetItemsProcessed(int64_t(st.iterations() * samples));
            if (input->meta.bytes > 0) st.SetBytesProcessed(int64_t(double(st.iterations()) * input->meta.bytes));
            st.counters["build_ms"] = 1e3 * build / double(st.iterations());
            st.counters["size"] = sized ? opts.width : input->meta.width;
            st.counters["first_ms"] = 1e3 * *cold;  // cold: fresh output pages, thread start (see above)
            st.counters["first_faults"] = *cold_faults;
            st.counters["first_cpu_ms"] = 1e3 * *cold_cpu;
            if (*session_start >= 0) st.counters["session_ms"] = 1e3 * *session_start;
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
  lockstep::keep_freed_memory();
  // Inputs that live beside the repository: the SPD scenes are generated when
  // absent (registry/loaders.h); the real volumes cannot be, and their frames go.
  if (!std::filesystem::is_directory(lockstep::spd_dir()))
    std::fprintf(stderr, "lockstep_bench: note: no %s: SPD scenes are generated (lockstep spd)\n",
                 lockstep::spd_dir().c_str());
  if (!lockstep::have_real_volumes())
    std::fprintf(stderr,
                 "lockstep_bench: note: cthead.nhdr or ch2.nhdr not in %s: frames of a missing volume "
                 "are skipped (the analytic fields run)\n",
                 lockstep::volumes_dir().c_str());
  // TBB starts once per process while the benchmarks register, as the CLI
  // starts it while its input loads (optimized/tiling.h): first_ms is then
  // the first frame of a process whose thread pool is up, as a CLI frame is.
  std::optional<lockstep::opt::ThreadPoolStart> pool(std::in_place);
  try {
    lockstep::register_kernels(lockstep::registry());
    lockstep::register_frames(lockstep::registry());
  } catch (const lockstep::InputError& e) {
    std::fprintf(stderr, "lockstep_bench: %s\n", e.what());
    return 2;
  }
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 2;
  pool.reset();
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
